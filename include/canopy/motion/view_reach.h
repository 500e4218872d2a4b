#pragma once
// The arm's side of view planning at a base stop, shared by the mission and by `canopy nbv`
// (planning from a saved map on a real robot): the paper's reachability filter as the view
// planner's candidate filter, the IK goals of a view, the tour order of a batch, and the
// whole "next views from a map" step.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "canopy/mapping/semantic_octree.h"
#include "canopy/motion/collision.h"
#include "canopy/motion/motion_config.h"
#include "canopy/motion/workspace_filter.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/nbv/voxel_index.h"

namespace canopy::motion {

/// The workspace filter (move into the workspace, IK, collision-free with `checker` when
/// given) as a candidate filter for the base at `base`; `arm_now` gives the arm's joints at
/// the time of each call (they seed the IK choice).
nbv::CandidateFilter reach_filter(const WorkspaceFilter& workspace, const BasePose& base,
                                  std::function<ArmConfig()> arm_now, const CollisionChecker* checker);

/// IK goals of a view for the base at `base`: the reachability check's answer first, then
/// every other solution within the joint limits (nearest to `seed` first).
std::vector<ArmConfig> view_goal_configs(const RobotModel& model, const nbv::PlannedView& view, const BasePose& base,
                                         const ArmConfig& seed);

/// The arm planner's goal test ahead of execution: true when one of the view's IK goals
/// (view_goal_configs) is free in `checker` (null: any IK goal will do). A view that fails it
/// fails before the arm moves (no_ik, goal_in_collision).
bool has_free_goal(const RobotModel& model, const CollisionChecker* checker, const nbv::PlannedView& view,
                   const BasePose& base, const ArmConfig& seed);

/// Orders views by an open tour from the arm at `q0` (TourParams: joint or Cartesian
/// cost). Views without IK go to `unreachable` (may be null); the others get has_q and q.
std::vector<nbv::PlannedView> tour_order(const RobotModel& model, const TourParams& params, const BasePose& base,
                                         const ArmConfig& q0, std::vector<nbv::PlannedView> views,
                                         std::vector<nbv::PlannedView>* unreachable);

/// Occupied voxel centres of a map (p_occ > 0.5, pruned blocks expanded): the planner's
/// collision environment.
std::vector<Vec3> occupied_voxel_centres(const mapping::SemanticOcTree& map);

/// One planning step at a stop: where the robot is and what it asks for.
struct NextViewsRequest {
  BasePose base;
  ArmConfig q{};                 ///< The arm now (tour start, IK seed).
  /// The camera now; when unset, forward kinematics of (base, q). (The mission passes the
  /// pose the simulator reports.)
  std::optional<Pose> T_world_camera;
  Eigen::AlignedBox3d region;    ///< Clusters must lie in it.
  int budget = 1;                ///< Views wanted.
  std::uint64_t seed = 1;
  std::vector<Pose> scripted;    ///< The stop's scripted views (for planners that take them).
  nbv::CandidateObserver on_scored;  ///< Passed to the planner (ViewRequest::on_scored).
  /// The batch is cut to its first max_views views (best first) before the tour: the attempts
  /// the stop has left (0: no cap).
  std::size_t max_views = 0;
  /// Views that failed here for a cause of their own (nbv::joins_failed_views): a batch's view
  /// within them is dropped before the tour and counted in NextViews::guarded, whatever the
  /// planner (the mission's guard; a Python planner may ignore request.failed_views). May be null.
  const nbv::TakenViews* failed = nullptr;
};

/// The arm's side of a stop: what reachability and the tour are computed with.
struct StopArm {
  const RobotModel& model;
  const WorkspaceFilter& workspace;
  const CollisionChecker* checker;  ///< Candidates must be collision-free with it; may be null.
  const TourParams& tour;
};

/// Its answer: the planner's batch and the views in execution order.
struct NextViews {
  nbv::ViewBatch batch;
  std::vector<nbv::PlannedView> ordered;      ///< Tour order (kTour) or the planner's order.
  std::vector<nbv::PlannedView> unreachable;  ///< Chosen views without an IK solution.
  std::size_t cleared_voxels = 0;             ///< Map voxels inside the robot, not obstacles.
  std::size_t guarded = 0;                    ///< Views of the batch dropped: in NextViewsRequest::failed.
};

/// The step the mission takes at every planning round and `canopy nbv` once: the planner's
/// batch for the robot at request.base against `map` (the workspace filter and IK as the
/// candidate filter, the workspace as the position test), without the views that failed here
/// (request.failed), then the views in execution order (the open tour for kTour batches). `index` is kept beside `map`. Deterministic.
NextViews next_views(const mapping::SemanticOcTree& map, nbv::VoxelIndex& index, nbv::ViewPlanner& planner,
                     const StopArm& arm, const NextViewsRequest& request);

/// next_views from a saved map: the map's occupied voxels as the collision environment
/// (minus the robot's own volume).
NextViews plan_next_views(const mapping::SemanticOcTree& map, nbv::ViewPlanner& planner, const RobotModel& model,
                          const MotionConfig& config, const NextViewsRequest& request);

}  // namespace canopy::motion
