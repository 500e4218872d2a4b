// The next-views job (jobs/next_views_job.h), what canopy nbv and canopy.next_views both call:
// for every method of the registry it plans as the step it wraps (motion::plan_next_views with
// the stop's region and budget); an oracle and joints outside the limits are refused with one line.

#include <gtest/gtest.h>

#include "../nbv/scene.h"
#include "canopy/common/error.h"
#include "canopy/jobs/next_views_job.h"
#include "canopy/mission/mission.h"
#include "canopy/nbv/planners/planners.h"

namespace canopy::jobs {
namespace {

struct NextViewsSetup {
  mapping::SemanticOcTree map = nbv_test::scanned_map();
  motion::RobotModel robot = motion::RobotModel::load(default_robot_config());
  settings::Settings settings = settings::Settings::defaults(default_robot_config());
  NextViewsJob job;
  NextViewsSetup() {
    // The arm base beside the scanned fruits (x = 0.5 m), the arm facing them.
    job.base = BasePose{0.5 - robot.T_base_arm().translation().x(), -0.55, 0.0};
    job.seed = 3;
  }
};

TEST(NextViewsJob, EveryMethodPlansAsTheStepItWraps) {
  NextViewsSetup s;
  int planned = 0;
  for (const nbv::ViewPlannerEntry& e : nbv::builtin_view_planners()) {
    if (e.reads_ground_truth) continue;
    SCOPED_TRACE(e.name);
    settings::Settings settings = s.settings;
    settings.set("method.name", e.name, "test");
    const NextViewsJobResult r = next_views(s.map, settings, s.robot, s.job);
    EXPECT_EQ(r.method.name, e.name);
    EXPECT_EQ(r.joints, s.robot.config().home);
    EXPECT_EQ(r.budget, settings.mission.loop.views_per_stop);
    // The same step assembled by hand.
    nbv::ViewPlannerSettings ps;
    ps.params = settings.nbv;
    ps.method = settings.method;
    const auto planner = nbv::make_view_planner(ps);
    motion::NextViewsRequest req;
    req.base = s.job.base;
    req.q = s.robot.config().home;
    const Vec3 arm = motion::RobotModel::T_world_base(s.job.base) * s.robot.T_base_arm().translation();
    req.region = mission::stop_region(settings.mission.loop, arm.x(), arm.y());
    req.budget = settings.mission.loop.views_per_stop;
    req.seed = s.job.seed;
    const motion::NextViews want = motion::plan_next_views(s.map, *planner, s.robot, settings.motion, req);
    EXPECT_TRUE(r.region.min().isApprox(req.region.min()) && r.region.max().isApprox(req.region.max()));
    EXPECT_TRUE(r.region.min() == stop_region_at(settings, s.robot, s.job.base).min());
    EXPECT_EQ(r.next.batch.clusters, want.batch.clusters);
    EXPECT_EQ(r.next.batch.candidates, want.batch.candidates);
    EXPECT_EQ(r.next.batch.reason, want.batch.reason);
    ASSERT_EQ(r.next.ordered.size(), want.ordered.size());
    for (std::size_t i = 0; i < want.ordered.size(); ++i) {
      EXPECT_TRUE(r.next.ordered[i].T_world_camera.isApprox(want.ordered[i].T_world_camera));
      EXPECT_EQ(r.next.ordered[i].gain, want.ordered[i].gain);
    }
    EXPECT_EQ(r.next.unreachable.size(), want.unreachable.size());
    planned += r.next.batch.clusters > 0;
  }
  EXPECT_GE(planned, 3);  // the map-based planners see the scene's two fruits
}

TEST(NextViewsJob, OraclesAndJointsOutsideTheLimitsAreRefusedWithOneLine) {
  NextViewsSetup s;
  for (const nbv::ViewPlannerEntry& e : nbv::builtin_view_planners()) {
    if (!e.reads_ground_truth) continue;
    settings::Settings settings = s.settings;
    settings.set("method.name", e.name, "test");
    try {
      next_views(s.map, settings, s.robot, s.job);
      ADD_FAILURE() << e.name << " planned without a mission";
    } catch (const InputError& err) {
      const std::string what = err.what();
      EXPECT_NE(what.find("reads the ground truth"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  NextViewsJob job = s.job;
  job.joints = ArmConfig{9, 9, 9, 9, 9, 9};
  job.joints_where = "--joints";
  try {
    next_views(s.map, s.settings, s.robot, job);
    ADD_FAILURE() << "joints outside the limits accepted";
  } catch (const InputError& err) {
    EXPECT_EQ(std::string(err.what()), "--joints: value '9,9,9,9,9,9' is outside the joint limits");
  }
  // Joints within the limits are the tour's start.
  job.joints = s.robot.config().home;
  (*job.joints)[0] += 0.1;
  EXPECT_EQ(next_views(s.map, s.settings, s.robot, job).joints, *job.joints);
}

}  // namespace
}  // namespace canopy::jobs
