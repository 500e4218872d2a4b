// A recording mapped (McapFrames into map_recorded, what `canopy map --mcap` does): a mission's
// own MCAP maps back to the mission's map.csm byte for byte; topics and frames are chosen from
// the recording when they are unambiguous (and refused, naming the candidates, when not); a
// truncated file, a missing transform, an unknown depth encoding, stamps that go back and a
// --frame other than the images' are each one line and leave no output folder.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/mcap_frames.h"
#include "canopy/jobs/recorded_map_job.h"
#include "canopy/ros2/mcap_reader.h"
#include "canopy/ros2/mcap_writer.h"
#include "mcap_mission.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;
namespace msg = ros2::msg;

RecordedMapResult map_mcap(const std::string& path, const McapFrameOptions& o, const std::string& out) {
  fs::remove_all(out);
  McapFrames frames(path, o);
  RecordedMapParams p;
  p.settings = test::round_trip_settings();
  if (!o.label_images) p.settings.mapping.extractor.source = perception::LabelSource::kColor;
  p.out = out;
  return map_recorded(frames.sequence(), p);
}

TEST(McapFrames, AMissionsRecordingMapsBackToItsMapByteForByte) {
  const test::RecordedMission& m = test::recorded_mission();
  McapFrameOptions o;
  o.label_images = true;
  McapFrames frames(m.mcap, o);
  EXPECT_EQ(frames.options().depth, "/canopy/wrist/depth");
  EXPECT_EQ(frames.options().rgb, "/canopy/wrist/rgb");
  EXPECT_EQ(frames.options().camera_info, "/canopy/wrist/camera_info");
  EXPECT_EQ(frames.options().frame, "camera_optical_frame");
  EXPECT_EQ(frames.options().world_frame, "world");
  ASSERT_EQ(frames.choices().size(), 5u);
  EXPECT_EQ(frames.choices().back(), "--world-frame world (the root of the camera's transform tree)");
  const std::string out = testing::TempDir() + "/mcap_round_trip";
  const RecordedMapResult r = map_mcap(m.mcap, o, out);
  EXPECT_EQ(r.mapped, m.result.successful_views());
  EXPECT_EQ(r.skipped, 0u);
  EXPECT_TRUE(read_file(out + "/map.csm") == read_file(m.run + "/map.csm")) << "the map differs from the mission's";
}

// Writes a recording as a lab's recorder would, from a mission's: its depth, colour and
// camera_info under `topics`, transforms as `tf` decides; `depth16` converts depth to 16UC1.
struct LabRecording {
  std::string rgb = "/camera/color/image_raw", depth = "/camera/aligned_depth_to_color/image_raw",
              camera_info = "/camera/color/camera_info";
  bool with_tf = true, depth16 = false, extra_depth = false, reversed_stamp = false;
};

std::string write_lab(const std::string& from, const std::string& path, const LabRecording& lab) {
  fs::remove(path);
  ros2::McapReader in(from);
  ros2::McapWriter out(path);
  const auto rgb = out.add_channel<msg::Image>(lab.rgb);
  const auto depth = out.add_channel<msg::Image>(lab.depth);
  const auto depth2 = lab.extra_depth ? out.add_channel<msg::Image>("/camera/depth/image_rect_raw") : 0;
  const auto info = out.add_channel<msg::CameraInfo>(lab.camera_info);
  const auto tf = out.add_channel<msg::TFMessage>("/tf");
  const auto tf_static = out.add_channel<msg::TFMessage>("/tf_static");
  int depth_count = 0;
  msg::Time first_depth;
  in.for_each_message([&](const ros2::McapMessage& m) {
    const std::string& t = m.channel->topic;
    if (t == "/canopy/wrist/rgb") out.write(rgb, m.log_time_ns, in.decode<msg::Image>(m));
    if (t == "/canopy/wrist/camera_info") out.write(info, m.log_time_ns, in.decode<msg::CameraInfo>(m));
    if (t == "/canopy/wrist/depth") {
      msg::Image d = in.decode<msg::Image>(m);
      if (++depth_count == 1) first_depth = d.header.stamp;
      if (lab.reversed_stamp && depth_count == 3) d.header.stamp = first_depth;  // back to the first's
      if (lab.depth16) {
        msg::Image mm = d;
        mm.encoding = "16UC1";
        mm.step = d.width * 2;
        mm.data.assign(std::size_t(d.width) * d.height * 2, 0);
        for (std::size_t i = 0; i < std::size_t(d.width) * d.height; ++i) {
          float z;
          std::memcpy(&z, d.data.data() + 4 * i, 4);
          const std::uint16_t v = std::isfinite(z) ? std::uint16_t(std::lround(z * 1000.0f)) : 0;
          std::memcpy(mm.data.data() + 2 * i, &v, 2);
        }
        d = mm;
      }
      out.write(depth, m.log_time_ns, d);
      if (depth2) out.write(depth2, m.log_time_ns, d);
    }
    if (lab.with_tf && t == "/tf") out.write(tf, m.log_time_ns, in.decode<msg::TFMessage>(m));
    if (lab.with_tf && t == "/tf_static") out.write(tf_static, m.log_time_ns, in.decode<msg::TFMessage>(m));
    return true;
  });
  out.close();
  return path;
}

std::string refusal(const std::string& path, McapFrameOptions o, const std::string& out) {
  try {
    map_mcap(path, o, out);
  } catch (const InputError& e) {
    EXPECT_FALSE(fs::exists(out)) << out;
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    return what;
  }
  return "(accepted)";
}

TEST(McapFrames, ChoosesRealSenseTopicsAndMapsSixteenBitDepth) {
  const test::RecordedMission& m = test::recorded_mission();
  const std::string dir = testing::TempDir();
  LabRecording lab;
  lab.depth16 = true;
  lab.extra_depth = true;  // the unaligned depth beside the aligned one
  const std::string path = write_lab(m.mcap, dir + "/realsense.mcap", lab);
  McapFrameOptions o;  // colour segmentation: no labels
  McapFrames frames(path, o);
  EXPECT_EQ(frames.options().depth, "/camera/aligned_depth_to_color/image_raw");
  EXPECT_EQ(frames.options().rgb, "/camera/color/image_raw");
  EXPECT_EQ(frames.options().camera_info, "/camera/color/camera_info");
  const RecordedMapResult r = map_mcap(path, o, dir + "/realsense_map");
  EXPECT_EQ(r.mapped, m.result.successful_views());
  EXPECT_GT(r.occupied_voxels, 1000u);
  // run.yaml names the recording and what was chosen from it; the job adds the mask noise last.
  const YAML::Node run = YAML::LoadFile(dir + "/realsense_map/run.yaml");
  EXPECT_EQ(run["command"].as<std::string>(), "map");
  EXPECT_EQ(run["mcap"].as<std::string>(), path);
  EXPECT_EQ(run["topics"]["depth"].as<std::string>(), "/camera/aligned_depth_to_color/image_raw");
  EXPECT_EQ(run["topics"]["rgb"].as<std::string>(), "/camera/color/image_raw");
  EXPECT_FALSE(run["topics"]["labels"]) << "colour segmentation reads no label topic";
  EXPECT_EQ(run["labels"].as<std::string>(), "color");
  EXPECT_EQ(run["max_time_diff_s"].as<double>(), o.max_dt_s);
  EXPECT_EQ(run["range_m"].as<std::vector<double>>(), (std::vector<double>{frames.options().min_range_m,
                                                                           frames.options().max_range_m}));
  ASSERT_GT(run.size(), 0u);
  std::string last;
  for (const auto& kv : run) last = kv.first.as<std::string>();
  EXPECT_EQ(last, "p_gt");
  EXPECT_EQ(run["p_gt"].as<double>(), 1.0);
}

TEST(McapFrames, RefusesInOneLineAndWritesNothing) {
  const test::RecordedMission& m = test::recorded_mission();
  const std::string dir = testing::TempDir(), out = dir + "/refused_map";
  McapFrameOptions o;
  // Truncated.
  const std::string bytes = read_file(m.mcap);
  const std::string cut = dir + "/cut.mcap";
  {
    std::ofstream f(cut, std::ios::binary);
    f << bytes.substr(0, bytes.size() / 2);
  }
  EXPECT_NE(refusal(cut, o, out).find("truncated MCAP file"), std::string::npos);
  // No transforms.
  LabRecording no_tf;
  no_tf.with_tf = false;
  EXPECT_EQ(refusal(write_lab(m.mcap, dir + "/no_tf.mcap", no_tf), o, out),
            dir + "/no_tf.mcap: no /tf or /tf_static: the camera's pose cannot be known");
  // Two depth topics, neither aligned: ambiguous.
  LabRecording two;
  two.depth = "/camera/depth2/image_raw";
  two.extra_depth = true;
  EXPECT_EQ(refusal(write_lab(m.mcap, dir + "/two.mcap", two), o, out),
            dir + "/two.mcap: several depth image (16UC1, mono16, 32FC1) topics (/camera/depth/image_rect_raw, "
                  "/camera/depth2/image_raw): name one with --depth");
  // Stamps that go back.
  LabRecording back;
  back.reversed_stamp = true;
  const std::string went_back = refusal(write_lab(m.mcap, dir + "/back.mcap", back), o, out);
  EXPECT_NE(went_back.find("/camera/aligned_depth_to_color/image_raw: header stamps do not increase"), std::string::npos)
      << went_back;
  // A frame other than the images'; a world frame in no tree; a missing topic; a wrong type.
  const std::string lab = write_lab(m.mcap, dir + "/lab.mcap", LabRecording{});
  o.frame = "camera_link";
  EXPECT_NE(refusal(lab, o, out).find("--frame camera_link: the depth images are in 'camera_optical_frame'"),
            std::string::npos);
  o.frame.clear();
  o.world_frame = "map";
  EXPECT_NE(refusal(lab, o, out).find("--world-frame map: in neither /tf nor /tf_static"), std::string::npos);
  o.world_frame.clear();
  o.rgb = "/camera/infra1/image_rect_raw";
  EXPECT_NE(refusal(lab, o, out).find("--rgb /camera/infra1/image_rect_raw: no such topic (the recording has"),
            std::string::npos);
  o.rgb = "/camera/color/camera_info";
  EXPECT_NE(refusal(lab, o, out).find("a topic of type sensor_msgs/msg/CameraInfo, not"), std::string::npos);
  o.rgb.clear();
  o.label_images = true;
  EXPECT_NE(refusal(lab, o, out).find("--seg truth reads label images"), std::string::npos);
}

}  // namespace
}  // namespace canopy::jobs
