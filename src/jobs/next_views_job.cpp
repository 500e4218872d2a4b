#include "canopy/jobs/next_views_job.h"

#include "canopy/common/error.h"
#include "canopy/mission/mission.h"

namespace canopy::jobs {

namespace {

ArmConfig checked_joints(const motion::RobotModel& robot, const NextViewsJob& job) {
  if (!job.joints) return robot.config().home;
  if (!robot.within_limits(*job.joints)) {
    std::string text;
    for (double q : *job.joints) text += (text.empty() ? "" : ",") + params_detail::shortest(q);
    throw InputError(job.joints_where + ": value '" + text + "' is outside the joint limits");
  }
  return *job.joints;
}

}  // namespace

Eigen::AlignedBox3d stop_region_at(const settings::Settings& settings, const motion::RobotModel& robot,
                                   const BasePose& base) {
  const Vec3 arm = motion::RobotModel::T_world_base(base) * robot.T_base_arm().translation();
  return mission::stop_region(settings.mission.loop, arm.x(), arm.y());
}

NextViewsJobResult next_views(const mapping::SemanticOcTree& map, const settings::Settings& settings,
                              const motion::RobotModel& robot, const NextViewsJob& job) {
  NextViewsJobResult out;
  out.method = settings.method;
  out.joints = checked_joints(robot, job);
  const nbv::ViewPlannerSettings ps = canopy::settings::planner_settings(settings, job.intrinsics.value_or(CameraIntrinsics{}));
  const std::unique_ptr<nbv::ViewPlanner> planner = nbv::make_view_planner(ps, "method");

  motion::NextViewsRequest req;
  req.base = job.base;
  req.q = out.joints;
  req.region = stop_region_at(settings, robot, job.base);
  req.budget = settings.mission.loop.views_per_stop;
  req.seed = job.seed;
  out.region = req.region;
  out.budget = req.budget;
  out.next = motion::plan_next_views(map, *planner, robot, settings.motion, req);
  return out;
}

}  // namespace canopy::jobs
