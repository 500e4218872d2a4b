// The motion benchmark (jobs/bench_motion.h) on a few samples: its figures are consistent with
// each other and its JSON has the keys `canopy bench motion --json` always wrote.

#include <gtest/gtest.h>

#include "canopy/jobs/bench_motion.h"

namespace canopy::jobs {
namespace {

TEST(BenchMotion, FiguresAreConsistentAndKeyedAsBefore) {
  BenchMotionParams p;
  p.world_file = "worlds/small.yaml";
  p.motion = motion::MotionConfig::defaults(default_robot_config());
  p.base = BasePose{-0.5, 0.0, 0.0};
  p.ik_poses = 200;
  p.states = 200;
  p.goals = 3;
  const BenchMotionResult r = bench_motion(p);
  EXPECT_GT(r.ik_us, 0.0);
  EXPECT_GT(r.ik_solutions_per_pose, 1.0);  // random reachable poses: several IK branches each
  EXPECT_LE(r.camera_ik_solutions_per_pose, r.ik_solutions_per_pose);
  EXPECT_GT(r.map_voxels, 0u);
  EXPECT_GE(r.colliding_fraction, 0.0);
  EXPECT_LT(r.colliding_fraction, 1.0);
  EXPECT_EQ(r.free_states_colliding, 0u);  // a state found free stays free
  EXPECT_EQ(r.goals, 3);
  int counted = 0;
  for (const auto& [status, n] : r.statuses) counted += n;
  EXPECT_EQ(counted, r.goals);
  EXPECT_LE(r.direct, r.planned);
  EXPECT_LE(r.median_s, r.p90_s);
  EXPECT_LE(r.p90_s, r.max_s);
  const nlohmann::json j = r.to_json();
  for (const char* key : {"ik_us_per_solve", "camera_ik_us_per_solve", "fk_us_per_call", "ik_solutions_per_pose",
                          "validity_us_per_state", "validity_free_us_per_state", "map_voxels", "planner",
                          "planning_goals", "planning_success_rate", "planning_direct", "planning_median_s",
                          "planning_p90_s", "planning_max_s", "planning_statuses", "motion_config"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j.at("planning_success_rate").get<double>(), double(r.planned) / r.goals);
  EXPECT_EQ(j.at("motion_config").at("seed"), p.motion.seed);
}

}  // namespace
}  // namespace canopy::jobs
