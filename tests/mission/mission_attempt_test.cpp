// One attempt of a view (mission_attempt.cpp, Mission::attempt): the planner's outcome mapped
// to the record's failure cause (failure_of_plan for the arm planner's statuses, no_ik before
// any plan), the record's bookkeeping, and a successful view's frame from the reached pose.
// The faults that need a scene of their own (a goal inside a plant, through the base, a
// diverging simulation) are MissionFaults in mission_test.cpp.

#include <gtest/gtest.h>

#include "canopy/mission/mission.h"

namespace canopy::mission {
namespace {

using namespace canopy::records;

TEST(MissionAttempt, EveryPlanStatusMapsToItsFailureCause) {
  EXPECT_EQ(failure_of_plan(motion::PlanStatus::kSuccess), FailureCause::kNone);
  EXPECT_EQ(failure_of_plan(motion::PlanStatus::kNoIk), FailureCause::kNoIk);
  EXPECT_EQ(failure_of_plan(motion::PlanStatus::kStartInCollision), FailureCause::kStartInCollision);
  EXPECT_EQ(failure_of_plan(motion::PlanStatus::kGoalInCollision), FailureCause::kGoalInCollision);
  EXPECT_EQ(failure_of_plan(motion::PlanStatus::kTimeout), FailureCause::kPlanTimeout);
  EXPECT_EQ(failure_of_plan(motion::PlanStatus::kInvalidInput), FailureCause::kInvalidInput);
}

TEST(MissionAttempt, RecordsEachAttemptWithItsCause) {
  const world::World world = world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")));
  settings::Settings s = settings::Settings::defaults(default_robot_config());
  s.mapping.extractor.source = perception::LabelSource::kTruth;
  s.mission.stops.count = 1;
  Mission mission(world, s, 1);
  ASSERT_TRUE(mission.drive_to_stop(0));
  const ArmConfig q0 = mission.simulator().arm_positions();

  // Far beyond the arm: no IK, recorded before any plan or move.
  nbv::PlannedView far;
  far.T_world_camera = look_at(Vec3(5.0, 5.0, 1.0), Vec3(5.0, 6.0, 1.0));
  far.gain = 0.25;
  far.cluster = 2;
  far.source = "nbv";
  const ViewRecord a = mission.attempt(far, ViewPhase::kNbv);
  EXPECT_FALSE(a.success);
  EXPECT_EQ(a.failure, FailureCause::kNoIk);
  EXPECT_EQ(a.message, "no IK solution within the joint limits");
  EXPECT_EQ(a.attempt, 0);
  EXPECT_EQ(a.phase, ViewPhase::kNbv);
  EXPECT_EQ(a.source, "nbv");
  EXPECT_EQ(a.gain, 0.25);
  EXPECT_EQ(a.cluster, 2);
  EXPECT_TRUE(a.T_goal.isApprox(far.T_world_camera));
  EXPECT_EQ(a.successful_views, 0);
  EXPECT_EQ(a.move_time_s, 0.0);
  EXPECT_EQ(mission.result().failures.at(to_string(FailureCause::kNoIk)), 1);
  const ArmConfig q1 = mission.simulator().arm_positions();
  for (int i = 0; i < kArmDof; ++i) EXPECT_EQ(q1[i], q0[i]);  // nothing moved

  // The stop's first scan view: taken, its frame from the pose reached, near the goal.
  nbv::PlannedView scan;
  scan.T_world_camera = mission.scan_views(0, false).front();
  const ViewRecord b = mission.attempt(scan, ViewPhase::kInitial);
  ASSERT_TRUE(b.success) << to_string(b.failure) << ": " << b.message;
  EXPECT_EQ(b.failure, FailureCause::kNone);
  EXPECT_EQ(b.attempt, 1);
  EXPECT_EQ(b.source, "initial");  // the initial scan's views say so
  EXPECT_EQ(b.successful_views, 1);
  EXPECT_GT(b.move_time_s, 0.0);
  EXPECT_LT((b.T_reached.translation() - scan.T_world_camera.translation()).norm(), 0.02);
  EXPECT_GT(b.target_points, 0);
  EXPECT_EQ(mission.result().views.size(), 2u);
  EXPECT_EQ(mission.result().successful_views(), 1);
}

}  // namespace
}  // namespace canopy::mission
