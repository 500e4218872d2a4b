// The mission job: its run folder holds what mission::Mission gives on its own (views.csv byte
// for byte, the same final map), a stop request before the start writes nothing, and the video
// options are checked with the names the caller gives them.

#include <gtest/gtest.h>

#include <filesystem>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/jobs/world_job.h"
#include "canopy/mapping/map_io.h"
#include "canopy/records/run_folder.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;

settings::Settings quick_settings() {
  settings::Settings s = settings::Settings::defaults(default_robot_config());
  s.mapping.extractor.source = perception::LabelSource::kTruth;
  s.mission.stops.count = 1;
  s.mission.loop.views_per_stop = 1;
  return s;
}

const world::World& small() {
  static const world::World w = build_world(load_world_spec("worlds/small.yaml"));
  return w;
}

TEST(MissionJob, RunFolderHoldsWhatTheMissionGivesOnItsOwn) {
  const std::string out = testing::TempDir() + "/mission_job_run";
  fs::remove_all(out);
  MissionJobParams p;
  p.world_file = "worlds/small.yaml";
  p.settings = quick_settings();
  p.seed = 5;
  p.out = out;
  p.keep_map = true;
  const MissionJobResult r = run_mission_job(small(), p);
  ASSERT_TRUE(r.result.complete);
  ASSERT_TRUE(r.map);

  mission::Mission direct(small(), p.settings, p.seed);
  const records::MissionResult alone = direct.run();
  const std::string csv = records::views_csv(alone, p.settings.method.name);
  EXPECT_EQ(read_file(out + "/views.csv"), csv);
  EXPECT_EQ(records::views_csv(r.result, p.settings.method.name), csv);
  EXPECT_TRUE(r.map->identical(direct.map()));
  EXPECT_TRUE(mapping::load_map(out + "/map.csm").identical(direct.map()));
  EXPECT_EQ(r.summary["seed"], 5);
  EXPECT_FALSE(fs::exists(out + ".partial"));
  EXPECT_TRUE(r.video_error.empty());
  EXPECT_FALSE(r.dataset_written);
}

TEST(MissionJob, AStopRequestBeforeTheStartWritesNothing) {
  const std::string out = testing::TempDir() + "/mission_job_stopped";
  fs::remove_all(out);
  MissionJobParams p;
  p.settings = quick_settings();
  p.out = out;
  mission::MissionCallbacks cb;
  cb.stop_requested = [] { return true; };
  EXPECT_THROW(run_mission_job(small(), p, cb), Interrupted);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
}

// Stops beyond the base's joints are refused before any work, naming the setting; a stop the
// base does not reach in time fails the run: the result says which, never "all stops done".
TEST(MissionJob, StopsTheBaseCannotServeAreRefusedOrFailTheRun) {
  const std::string out = testing::TempDir() + "/mission_job_far";
  fs::remove_all(out);
  MissionJobParams p;
  p.settings = quick_settings();
  p.out = out;
  p.settings.mission.stops.positions_m = {0.0, 300.0};
  try {
    run_mission_job(small(), p);
    FAIL() << "a stop at x = 300 m accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("mission.stops.positions_m: stop 2 at x = 300 m", 0), 0u) << e.what();
  }
  p.settings.mission.stops.positions_m.clear();
  p.settings.mission.stops.base_y_m = -270.0;  // beyond the base_y joint (+-250 m)
  EXPECT_THROW(run_mission_job(small(), p), InputError);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));

  p.settings.mission.stops.base_y_m = 0.0;
  p.settings.mission.stops.timeout_s = 0.05;  // the base cannot drive 0.5 m in 0.05 s
  const MissionJobResult r = run_mission_job(small(), p);
  EXPECT_EQ(r.result.stops_not_reached(), 1);
  EXPECT_EQ(r.result.end_reason.rfind("1 of 1 stops not reached by the base (stop 1: base_failed)", 0), 0u)
      << r.result.end_reason;
  EXPECT_EQ(r.summary["end_reason"], r.result.end_reason);
}

TEST(MissionJob, VideoOptionsAreCheckedUnderTheCallersNames) {
  const std::string dir = testing::TempDir();
  const VideoOptions v = video_options(dir + "/v.mp4", "128x96", 4.0);
  EXPECT_EQ(v.width_px, 128);
  EXPECT_EQ(v.height_px, 96);
  EXPECT_EQ(v.fps, 4.0);
  EXPECT_TRUE(video_options("", "junk", -1.0).path.empty());  // no video: nothing to check
  auto message = [&](const std::string& size, double fps, const VideoOptionNames& names) {
    try {
      video_options(dir + "/v.mp4", size, fps, names);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message("65x64", 25, {}), "--video-size: '65x64' is not WxH with even sizes in [64, 1920] x [64, 1080]");
  for (const char* bad : {"64", "64x", "x64", "64x64x", "62x64", "1922x64", "64x1082"})
    EXPECT_NE(message(bad, 25, {}).find("--video-size: '"), std::string::npos) << bad;
  EXPECT_EQ(message("64x64", 0.0, {}), "--video-fps: must be in (0, 120]");
  EXPECT_EQ(message("64x64", 121.0, {"video", "video_size", "video_fps"}), "video_fps: must be in (0, 120]");
  EXPECT_EQ(message("66x63", 25, {"video", "video_size", "video_fps"}).rfind("video_size: '66x63'", 0), 0u);
  fs::create_directories(dir + "/a_folder.mp4");
  try {
    video_options(dir + "/a_folder.mp4", "64x64", 25, {"video", "video_size", "video_fps"});
    FAIL() << "a folder accepted as the video";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("video", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace canopy::jobs
