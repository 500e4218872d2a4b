#pragma once
// Job: the next views from a map for the robot at a base pose, by any method of the planner
// registry. What `canopy nbv` (views.json, for a real robot) and Python's canopy.next_views
// both do: the method's planner for the stop's region (the settings' mission.loop box around
// the arm base) and budget (mission.loop.views_per_stop), the workspace filter and IK against
// the map's occupied voxels, then the tour from the arm now. The front ends only translate
// their arguments into the settings and this job.

#include <cstdint>
#include <optional>
#include <string>

#include "canopy/common/camera.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/motion/view_reach.h"
#include "canopy/settings/settings.h"

namespace canopy::jobs {
/// The planner `canopy nbv` and Python's next_views use when none is named: learned, the planner a
/// lab deploys (issue 47's goal met, docs/real_robot.md); canopy run keeps the paper's ours.
inline constexpr const char* kNextViewsMethod = "learned";
}  // namespace canopy::jobs

namespace canopy::jobs {

/// Where the robot is and what else the planner is given.
struct NextViewsJob {
  BasePose base;
  /// The arm now (the tour's start, the IK seed); default: home. Refused outside the joint limits.
  std::optional<ArmConfig> joints;
  std::string joints_where = "joints";         ///< Names the joints in that message ("--joints").
  std::uint64_t seed = 1;                      ///< Seeds the planner's random draws.
  std::optional<CameraIntrinsics> intrinsics;  ///< Default: the D405 (CameraIntrinsics{}).
};

/// Its answer.
struct NextViewsJobResult {
  motion::NextViews next;        ///< The planner's batch, the views in tour order, those without IK.
  nbv::MethodChoice method;      ///< The method that planned (the settings' method section).
  ArmConfig joints{};            ///< The arm the tour started from.
  Eigen::AlignedBox3d region;    ///< The stop's region.
  int budget = 0;                ///< Views wanted (mission.loop.views_per_stop).
};

/// The stop's region for the robot at `base`: the settings' mission.loop box around the arm base
/// (what the planner's targets must lie in; canopy.Robot.stop_region).
Eigen::AlignedBox3d stop_region_at(const settings::Settings& settings, const motion::RobotModel& robot,
                                   const BasePose& base);

/// The next views by the planner settings.method names (any registered planner; an oracle,
/// which reads the ground truth, is refused with one line: there is none without a simulated
/// mission). Throws InputError for a bad method or joints. Deterministic.
NextViewsJobResult next_views(const mapping::SemanticOcTree& map, const settings::Settings& settings,
                              const motion::RobotModel& robot, const NextViewsJob& job);

}  // namespace canopy::jobs
