// canopy's MCAP against Foxglove's libraries (tests/ros2/reference, installed by the
// ros2.foxglove_install fixture): Foxglove's writer records a mission's frames as a lab's
// robot would (RealSense raw and PNG, ZED; /tf at 30 Hz through map, odom and base_link, the
// camera chain on /tf_static, depth 4 ms after colour, 2024 stamps) and `canopy map --mcap`'s job
// maps each as `canopy map --frames` maps the same frames; Foxglove's reader decodes every
// message of a mission's own MCAP (sizes, encodings, stamps, the tf tree, the description).

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>

#include "../ros2/foxglove_reference.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/datasets/frame_io.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/jobs/mcap_frames.h"
#include "canopy/jobs/recorded_map_job.h"
#include "canopy/mapping/map_io.h"
#include "mcap_mission.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;
using ros2::test::read_json;
using ros2::test::run_foxglove;

settings::Settings colour_settings() {
  settings::Settings s = test::round_trip_settings();
  s.mapping.extractor.source = perception::LabelSource::kColor;
  return s;
}

// The mission's frames as canopy frame folders, and as the raw files and poses the script reads.
struct LabFrames {
  std::string folders, spec;
  std::size_t count = 0;
};

const LabFrames& lab_frames() {
  static const LabFrames lab = [] {
    LabFrames l;
    const std::string dir = testing::TempDir() + "/lab_frames";
    fs::remove_all(dir);
    l.folders = dir + "/frames";
    fs::create_directories(l.folders);
    McapFrameOptions o;
    o.label_images = true;
    McapFrames recording(test::recorded_mission().mcap, o);
    RecordedSequence seq = recording.sequence();
    nlohmann::json spec = {{"start_ns", "1717000000000000000"}, {"frames", nlohmann::json::array()}};
    for (std::size_t i = 0; i < seq.size; ++i) {
      LabelledFrame f;
      std::string why;
      EXPECT_TRUE(seq.read(i, &f, &why)) << why;
      f.instance = Image<std::int32_t>(f.depth_m.width, f.depth_m.height, kNoInstance);
      char name[32];
      std::snprintf(name, sizeof name, "%03u", static_cast<unsigned>(i));
      const std::string folder = l.folders + "/" + name + "/";
      fs::create_directories(folder);
      datasets::write_frame(folder, f, seq.classes);
      // The depth exactly as the folder holds it (millimetres), and the colour, as raw files.
      const Image<std::uint16_t> mm = read_png_gray16(folder + "depth.png");
      write_file_atomic(dir + "/" + name + ".depth", std::string(reinterpret_cast<const char*>(mm.data.data()), mm.data.size() * 2));
      write_file_atomic(dir + "/" + name + ".rgb", std::string(reinterpret_cast<const char*>(f.rgb.data.data()), f.rgb.data.size() * 3));
      nlohmann::json pose = nlohmann::json::array();
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) pose.push_back(f.T_world_camera.matrix()(r, c));
      spec["frames"].push_back({{"rgb", dir + "/" + name + ".rgb"}, {"depth_mm", dir + "/" + name + ".depth"}, {"pose", pose}});
      if (i == 0) {
        const CameraIntrinsics& K = f.intrinsics;
        spec["width"] = K.width_px;
        spec["height"] = K.height_px;
        spec["fx"] = K.fx_px;
        spec["fy"] = K.fy_px;
        spec["cx"] = K.cx_px - 0.5;  // ROS: pixel centres at integer coordinates
        spec["cy"] = K.cy_px - 0.5;
      }
    }
    l.count = seq.size;
    l.spec = dir + "/spec.json";
    write_file_atomic(l.spec, spec.dump());
    return l;
  }();
  return lab;
}

// map.csm of the frame folders, as `canopy map --frames` writes it.
const std::string& frames_map() {
  static const std::string map = [] {
    const std::string out = testing::TempDir() + "/lab_frames_map";
    fs::remove_all(out);
    const datasets::FrameReaderOptions reader;
    const datasets::FrameSequence frames = datasets::FrameSequence::open(lab_frames().folders, reader);
    const RecordedSequence seq = frames_sequence(frames, reader);
    RecordedMapParams p;
    p.settings = colour_settings();
    p.out = out;
    EXPECT_EQ(map_recorded(seq, p).mapped, lab_frames().count);
    const YAML::Node run = YAML::LoadFile(out + "/run.yaml");  // what frames_sequence describes
    EXPECT_EQ(run["command"].as<std::string>(), "map");
    EXPECT_EQ(run["frames"].as<std::string>(), lab_frames().folders);
    EXPECT_EQ(run["layout"].as<std::string>(), "canopy");
    EXPECT_EQ(run["labels"].as<std::string>(), "color");
    EXPECT_EQ(run["classes"].as<std::vector<std::string>>(), frames.classes().names);
    EXPECT_EQ(run["max_time_diff_s"].as<double>(), reader.max_time_diff_s);
    EXPECT_EQ(run["p_gt"].as<double>(), p.settings.mapping.extractor.p_gt);
    return read_file(out + "/map.csm");
  }();
  return map;
}

void expect_lab_recording_maps_as_frames(const std::string& convention, const std::string& rgb,
                                         const std::string& depth, const std::string& camera) {
  const std::string mcap = testing::TempDir() + "/lab_" + convention + ".mcap";
  fs::remove(mcap);
  ASSERT_TRUE(run_foxglove({"write-lab", lab_frames().spec, mcap, convention}));
  McapFrames recording(mcap, McapFrameOptions{});
  EXPECT_EQ(recording.options().rgb, rgb);
  EXPECT_EQ(recording.options().depth, depth);
  EXPECT_EQ(recording.options().frame, camera);
  EXPECT_EQ(recording.options().world_frame, "map");
  const std::string out = testing::TempDir() + "/lab_" + convention + "_map";
  fs::remove_all(out);
  RecordedMapParams p;
  p.settings = colour_settings();
  p.out = out;
  const RecordedMapResult r = map_recorded(recording.sequence(), p);
  EXPECT_EQ(r.mapped, lab_frames().count);
  EXPECT_EQ(r.skipped, 0u);
  // The poses come through five transforms composed in doubles (and quaternions): the map is
  // the frames' own, voxel for voxel.
  const mapping::SemanticOcTree a = mapping::load_map(out + "/map.csm");
  const mapping::SemanticOcTree b = mapping::load_map(testing::TempDir() + "/lab_frames_map/map.csm");
  EXPECT_TRUE(read_file(out + "/map.csm") == frames_map() || a.identical(b))
      << convention << ": the map differs from canopy map --frames on the same frames";
}

TEST(McapFramesFoxglove, RealSenseRecordingMapsAsItsFrames) {
  frames_map();
  expect_lab_recording_maps_as_frames("realsense", "/camera/color/image_raw", "/camera/aligned_depth_to_color/image_raw",
                                      "camera_color_optical_frame");
}

TEST(McapFramesFoxglove, RealSensePngRecordingMapsAsItsFrames) {
  frames_map();
  expect_lab_recording_maps_as_frames("realsense-png", "/camera/color/image_raw/compressed",
                                      "/camera/aligned_depth_to_color/image_raw", "camera_color_optical_frame");
}

TEST(McapFramesFoxglove, ZedRecordingMapsAsItsFrames) {
  frames_map();
  expect_lab_recording_maps_as_frames("zed", "/zed/zed_node/rgb/image_rect_color", "/zed/zed_node/depth/depth_registered",
                                      "zed_left_camera_optical_frame");
}

TEST(McapJobFoxglove, FoxglovesReaderDecodesAMissionsRecording) {
  const test::RecordedMission& m = test::recorded_mission();
  const std::string json = testing::TempDir() + "/mission_dump.json";
  ASSERT_TRUE(run_foxglove({"dump", m.mcap, json}));
  const nlohmann::json d = read_json(json);
  EXPECT_EQ(d["header"]["profile"], "ros2");
  EXPECT_EQ(d["header"]["library"].get<std::string>().rfind("canopy ", 0), 0u);
  const std::int64_t epoch = m.summary["started_unix_ns"].get<std::int64_t>();
  std::map<std::string, std::size_t> count;
  std::map<std::string, std::string> parent;  // the tf tree, child -> parent
  const std::size_t views = m.result.successful_views();
  for (const nlohmann::json& x : d["messages"]) {
    const std::string topic = x["topic"];
    ++count[topic];
    EXPECT_TRUE(x["reencoded_equal"].get<bool>()) << topic;
    const nlohmann::json& v = x["value"];
    const std::int64_t log = std::stoll(x["log_time"].get<std::string>());
    EXPECT_GE(log, epoch);
    if (v.contains("header")) {
      const std::int64_t stamp = v["header"]["stamp"]["sec"].get<std::int64_t>() * 1000000000 +
                                 v["header"]["stamp"]["nanosec"].get<std::int64_t>();
      EXPECT_EQ(stamp, log) << topic;
    }
    if (x["schema"] == "sensor_msgs/msg/Image") {
      const int w = v["width"], h = v["height"];
      const std::string enc = v["encoding"];
      const int bytes = enc == "rgb8" ? 3 : enc == "32FC1" ? 4 : enc == "mono8" ? 1 : 0;
      EXPECT_GT(bytes, 0) << enc;
      EXPECT_EQ(v["step"].get<int>(), w * bytes);
      EXPECT_EQ(v["data"]["bytes"].get<int>(), w * h * bytes);
      EXPECT_EQ(v["header"]["frame_id"], "camera_optical_frame");
      EXPECT_EQ(enc, topic == "/canopy/wrist/depth" ? "32FC1" : topic == "/canopy/wrist/labels" ? "mono8" : "rgb8");
    }
    if (x["schema"] == "tf2_msgs/msg/TFMessage")
      for (const nlohmann::json& t : v["transforms"]) {
        const std::string child = t["child_frame_id"], up = t["header"]["frame_id"];
        EXPECT_TRUE(!parent.count(child) || parent[child] == up) << child;
        parent[child] = up;
      }
    if (topic == "/robot_description") {
      EXPECT_NE(v["data"].get<std::string>().find("<robot name="), std::string::npos);
    }
    if (topic == "/canopy/map") {
      EXPECT_EQ(v["point_step"], 24);
      EXPECT_EQ(v["fields"].size(), 6u);
      EXPECT_EQ(v["data"]["bytes"].get<int>(), v["width"].get<int>() * 24);
    }
  }
  EXPECT_EQ(count["/canopy/wrist/rgb"], views);
  EXPECT_EQ(count["/canopy/wrist/depth"], views);
  EXPECT_EQ(count["/canopy/map"], views);
  EXPECT_EQ(count["/tf_static"], 1u);
  EXPECT_EQ(count["/robot_description"], 1u);
  // The optical frame reaches world through the tree.
  std::string f = "camera_optical_frame";
  std::vector<std::string> chain = {f};
  while (parent.count(f) && chain.size() < 50) chain.push_back(f = parent[f]);
  EXPECT_EQ(chain.back(), "world");
  EXPECT_GT(chain.size(), 8u);
}

}  // namespace
}  // namespace canopy::jobs
