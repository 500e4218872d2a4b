// A mission recorded as MCAP while it runs (MissionJobParams::mcap) and a run folder exported
// (export_mcap): what the file holds (topics, counts, stamps from the epoch, the latched
// description, the fixed links once on /tf_static, the moving ones on /tf, images per view in
// both depth encodings), that recording changes nothing the mission does, that the export of
// the folder is the recording made while it ran, byte for byte, and what is refused.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/mcap_job.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/jobs/world_job.h"
#include "canopy/records/run_folder.h"
#include "canopy/ros2/mcap_reader.h"
#include "mcap_mission.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;
namespace msg = ros2::msg;
using test::recorded_mission;

std::size_t small_world_fruits() { return test::small_world().truth.fruits.size(); }

TEST(MissionMcap, HoldsTheRunAsItRan) {
  const test::RecordedMission& m = recorded_mission();
  ros2::McapReader in(m.mcap);
  in.verify();
  std::map<std::string, std::uint64_t> count;
  for (const ros2::McapTopic& t : in.topics()) count[t.topic] = t.message_count.value_or(0);
  const std::size_t views = m.result.successful_views();
  ASSERT_GT(views, 2u);
  for (const char* t : {recording_topics::kRgb, recording_topics::kDepth, recording_topics::kLabels,
                        recording_topics::kLabelsColor, recording_topics::kCameraInfo, recording_topics::kMap,
                        recording_topics::kViews})
    EXPECT_EQ(count[t], views) << t;
  EXPECT_EQ(count[recording_topics::kFruits], views + 1);  // at the start, then after each view
  EXPECT_EQ(count[recording_topics::kTfStatic], 1u);
  EXPECT_EQ(count[recording_topics::kRobotDescription], 1u);
  // /tf every 0.1 s of simulated time and at each view.
  EXPECT_GE(count[recording_topics::kTf], std::uint64_t(m.result.sim_time_s / 0.1));
  // Latched: rosbag2's transient_local durability on the two latched topics only.
  for (const auto& [id, c] : in.channels()) {
    const bool latched = c.topic == recording_topics::kTfStatic || c.topic == recording_topics::kRobotDescription;
    EXPECT_EQ(!c.metadata.empty() && c.metadata[0].second.find("durability: 1") != std::string::npos, latched) << c.topic;
  }

  const std::int64_t epoch = m.summary["started_unix_ns"].get<std::int64_t>();
  EXPECT_EQ(m.summary["recording"]["epoch_unix_ns"], epoch);
  std::set<std::string> fixed, moving;
  std::vector<double> view_times;
  for (const records::ViewRecord& v : m.result.views)
    if (v.success) view_times.push_back(v.sim_time_s);
  std::size_t view = 0;
  std::uint64_t first = 0, last = 0;
  msg::MarkerArray last_fruits;
  in.for_each_message([&](const ros2::McapMessage& x) {
    if (!first) first = x.log_time_ns;
    last = x.log_time_ns;
    const std::string& t = x.channel->topic;
    if (t == recording_topics::kTfStatic)
      for (const auto& e : in.decode<msg::TFMessage>(x).transforms) fixed.insert(e.child_frame_id);
    if (t == recording_topics::kTf)
      for (const auto& e : in.decode<msg::TFMessage>(x).transforms) moving.insert(e.child_frame_id);
    if (t == recording_topics::kRobotDescription) {
      EXPECT_NE(in.decode<msg::String>(x).data.find("<robot"), std::string::npos);
    }
    if (t == recording_topics::kFruits) last_fruits = in.decode<msg::MarkerArray>(x);
    if (t == recording_topics::kDepth) {
      const msg::Image d = in.decode<msg::Image>(x);
      EXPECT_EQ(d.encoding, "32FC1");
      EXPECT_EQ(d.step, d.width * 4);
      EXPECT_EQ(d.header.frame_id, "camera_optical_frame");
      // Stamped epoch + the view's simulated time.
      EXPECT_NEAR(double(std::int64_t(d.header.stamp.to_ns()) - epoch) / 1e9, view_times.at(view), 1e-3);
      EXPECT_EQ(d.header.stamp.to_ns(), x.log_time_ns);
      ++view;
    }
    return true;
  });
  EXPECT_EQ(view, views);
  // The last fruit markers carry each target fruit's coverage after the last view: the run's final.
  ASSERT_EQ(last_fruits.markers.size(), small_world_fruits());
  std::size_t target = 0;
  for (const msg::Marker& f : last_fruits.markers) {
    if (f.ns != "target fruits") continue;
    ASSERT_LT(target, m.result.final_metrics.fruits.size());
    EXPECT_NEAR(std::stod(f.text), m.result.final_metrics.fruits[target].coverage, 5e-4) << f.id;
    ++target;
  }
  EXPECT_EQ(target, m.result.final_metrics.fruits.size());
  EXPECT_GE(first, std::uint64_t(epoch));
  EXPECT_LE(last, std::uint64_t(epoch) + std::uint64_t((m.result.sim_time_s + 1.0) * 1e9));
  // The fixed links (the camera's chain on the tool) once, the joints' links on /tf; none in both.
  EXPECT_TRUE(fixed.count("camera_optical_frame"));
  EXPECT_TRUE(fixed.count("camera_link"));
  EXPECT_TRUE(moving.count("tool0") || moving.count("wrist_3_link"));
  EXPECT_TRUE(moving.count("base_x_link") || moving.count("base_link"));
  for (const std::string& f : fixed) EXPECT_FALSE(moving.count(f)) << f;
}

TEST(MissionMcap, RecordingChangesNothingTheMissionDoes) {
  const test::RecordedMission& m = recorded_mission();
  MissionJobParams p;
  p.settings = test::round_trip_settings();
  p.seed = test::kSeed;
  p.report = false;
  const MissionJobResult plain = run_mission_job(test::small_world(), p);
  EXPECT_EQ(records::views_csv(plain.result, p.settings.method.name), m.views_csv);
}

TEST(MissionMcap, TheExportOfTheRunFolderIsTheRecordingMadeWhileItRan) {
  const test::RecordedMission& m = recorded_mission();
  ExportMcapParams p;
  p.run_dir = m.run;
  p.mcap = mcap_record_options(testing::TempDir() + "/exported.mcap", "zstd", "32FC1", "run", "out", "--");
  fs::remove(p.mcap.path);
  const ros2::McapWriteStats s = export_mcap(p);
  EXPECT_EQ(s.messages, ros2::McapReader(m.mcap).message_count().value_or(0));
  EXPECT_TRUE(read_file(p.mcap.path) == read_file(m.mcap)) << "the export differs from the recording";

  // 16UC1 millimetres, 0 for no return, lz4 chunks, stamps from 1970.
  p.mcap = mcap_record_options(testing::TempDir() + "/exported16.mcap", "lz4", "16UC1", "zero", "out", "--");
  export_mcap(p);
  ros2::McapReader in(p.mcap.path);
  std::size_t zeros = 0, images = 0;
  in.for_each_message([&](const ros2::McapMessage& x) {
    if (x.channel->topic == recording_topics::kDepth) {
      const msg::Image d = in.decode<msg::Image>(x);
      EXPECT_EQ(d.encoding, "16UC1");
      EXPECT_EQ(d.step, d.width * 2);
      for (std::size_t i = 0; i + 1 < d.data.size(); i += 2) zeros += d.data[i] == 0 && d.data[i + 1] == 0;
      if (images++ == 0) {
        EXPECT_LT(x.log_time_ns, std::uint64_t(60e9));
      }
    }
    return true;
  });
  EXPECT_GT(images, 0u);
  EXPECT_GT(zeros, 0u);  // the background beyond the range
}

TEST(MissionMcap, RefusesWhatItCannotRecord) {
  const test::RecordedMission& m = recorded_mission();
  const auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string dir = testing::TempDir();
  EXPECT_EQ(message([&] { mcap_record_options(dir + "/a.bag", "zstd", "32FC1", "run"); }),
            "--mcap: " + dir + "/a.bag: an MCAP file's name ends in .mcap");
  EXPECT_EQ(message([&] { mcap_record_options(dir + "/a.mcap", "bz2", "32FC1", "run"); }),
            "--mcap-compression: 'bz2' is not none, lz4 or zstd");
  EXPECT_EQ(message([&] { mcap_record_options(dir + "/a.mcap", "zstd", "16UC2", "run"); }).rfind("--mcap-depth: '16UC2'", 0),
            0u);
  EXPECT_EQ(message([&] { mcap_record_options(dir + "/a.mcap", "zstd", "32FC1", "yesterday", "out", "--"); })
                .rfind("--epoch: 'yesterday' is not 'run'", 0),
            0u);
  // Not a run folder; a run whose views the replay does not give; a lab's file at the name.
  ExportMcapParams p;
  p.run_dir = dir;
  p.mcap = mcap_record_options(dir + "/refused.mcap", "zstd", "32FC1", "run");
  EXPECT_EQ(message([&] { export_mcap(p); }), dir + ": not a canopy mission run folder (no summary.json)");
  const std::string altered = dir + "/altered_run";
  fs::remove_all(altered);
  fs::copy(m.run, altered);
  std::string csv = read_file(m.run + "/views.csv");
  csv[csv.rfind(',') - 1] ^= 1;
  write_file_atomic(altered + "/views.csv", csv);
  p.run_dir = altered;
  EXPECT_NE(message([&] { export_mcap(p); }).find("replaying the run gave other views than its views.csv"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(p.mcap.path));
  write_file_atomic(dir + "/lab.mcap", "not canopy's");
  p.run_dir = m.run;
  p.mcap.path = dir + "/lab.mcap";
  EXPECT_NE(message([&] { export_mcap(p); }), "(accepted)");
  EXPECT_EQ(read_file(dir + "/lab.mcap"), "not canopy's");
}

}  // namespace
}  // namespace canopy::jobs
