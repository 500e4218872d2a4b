#pragma once
// One small mission recorded as MCAP while it ran, shared by the MCAP tests of the jobs module
// (run once per test binary): the small world, one stop, true labels without mask noise (what
// a recording can map back byte for byte), its run folder and its recording.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "canopy/common/read_file.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/jobs/world_job.h"
#include "canopy/records/run_folder.h"

namespace canopy::jobs::test {

constexpr std::uint64_t kSeed = 3;

inline settings::Settings round_trip_settings() {
  settings::Settings s = settings::Settings::defaults(default_robot_config());
  s.mapping.extractor.source = perception::LabelSource::kTruth;
  s.mapping.extractor.p_gt = 1.0;
  s.mission.stops.count = 1;
  s.mission.loop.views_per_stop = 2;
  return s;
}

inline const world::World& small_world() {
  static const world::World w = build_world(load_world_spec("worlds/small.yaml"));
  return w;
}

struct RecordedMission {
  std::string run, mcap, views_csv;
  records::MissionResult result;
  nlohmann::json summary;
};

inline const RecordedMission& recorded_mission() {
  static const RecordedMission m = [] {
    RecordedMission r;
    r.run = testing::TempDir() + "/mcap_mission_run";
    r.mcap = testing::TempDir() + "/mcap_mission.mcap";
    std::filesystem::remove_all(r.run);
    std::filesystem::remove(r.mcap);
    MissionJobParams p;
    p.world_file = "worlds/small.yaml";
    p.settings = round_trip_settings();
    p.seed = kSeed;
    p.out = r.run;
    p.report = false;
    p.mcap = mcap_record_options(r.mcap, "zstd", "32FC1", "run");
    const MissionJobResult j = run_mission_job(small_world(), p);
    EXPECT_TRUE(j.mcap_written);
    r.result = j.result;
    r.summary = j.summary;
    r.views_csv = read_file(r.run + "/views.csv");
    return r;
  }();
  return m;
}

}  // namespace canopy::jobs::test
