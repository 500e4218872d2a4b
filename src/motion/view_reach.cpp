#include "canopy/motion/view_reach.h"

#include <algorithm>

#include "canopy/motion/arm_planner.h"


namespace canopy::motion {

nbv::CandidateFilter reach_filter(const WorkspaceFilter& workspace, const BasePose& base,
                                  std::function<ArmConfig()> arm_now, const CollisionChecker* checker) {
  return [&workspace, base, arm_now = std::move(arm_now), checker](nbv::Candidate* c) {
    const FilteredView f = workspace.filter(base, c->T_world_camera, arm_now(), checker);
    if (!f.kept()) return false;
    c->T_world_camera = f.T_world_camera;
    c->shift_m = f.shift_m;
    c->has_q = true;
    c->q = f.q;
    return true;
  };
}

std::vector<ArmConfig> view_goal_configs(const RobotModel& model, const nbv::PlannedView& view, const BasePose& base,
                                         const ArmConfig& seed) {
  std::vector<ArmConfig> goals;
  if (view.has_q) goals.push_back(view.q);
  const IkResult ik = model.camera_ik(base, view.T_world_camera, seed);
  for (int i = 0; i < ik.count; ++i) {
    const ArmConfig& g = ik.q[static_cast<std::size_t>(i)];
    if (!view.has_q || joint_distance(g, view.q) > 1e-9) goals.push_back(g);
  }
  return goals;
}

bool has_free_goal(const RobotModel& model, const CollisionChecker* checker, const nbv::PlannedView& view,
                   const BasePose& base, const ArmConfig& seed) {
  for (const ArmConfig& g : view_goal_configs(model, view, base, seed))
    if (!checker || !checker->in_collision(base, g)) return true;
  return false;
}

std::vector<nbv::PlannedView> tour_order(const RobotModel& model, const TourParams& params, const BasePose& base,
                                         const ArmConfig& q0, std::vector<nbv::PlannedView> views,
                                         std::vector<nbv::PlannedView>* unreachable) {
  std::vector<nbv::PlannedView> reachable;
  std::vector<ArmConfig> qs;
  std::vector<Vec3> cams;
  for (nbv::PlannedView& v : views) {
    const std::vector<ArmConfig> goals = view_goal_configs(model, v, base, q0);
    if (goals.empty()) {
      if (unreachable) unreachable->push_back(v);
      continue;
    }
    if (!v.has_q) {
      v.has_q = true;
      v.q = goals.front();
    }
    reachable.push_back(v);
    qs.push_back(v.q);
    cams.push_back(v.T_world_camera.translation());
  }
  if (reachable.size() < 2) return reachable;
  const std::vector<int> order = order_views(params, q0, model.camera_pose(base, q0).translation(), qs, cams);
  std::vector<nbv::PlannedView> out;
  for (int i : order) out.push_back(reachable[static_cast<std::size_t>(i)]);
  return out;
}

std::vector<Vec3> occupied_voxel_centres(const mapping::SemanticOcTree& map) {
  std::vector<Vec3> out;
  map.for_each_voxel_if([](const mapping::SemanticState& s) { return s.occupancy_logodds() > 0.f; },
                        [&](const octomap::OcTreeKey& key, const mapping::SemanticState&) {
                          out.push_back(map.center_of(key));
                        });
  return out;
}

NextViews next_views(const mapping::SemanticOcTree& map, nbv::VoxelIndex& index, nbv::ViewPlanner& planner,
                     const StopArm& arm, const NextViewsRequest& request) {
  nbv::ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.T_world_camera = request.T_world_camera ? *request.T_world_camera : arm.model.camera_pose(request.base, request.q);
  req.region = request.region;
  req.budget = request.budget;
  req.seed = request.seed;
  req.scripted = request.scripted;
  req.has_q = true;
  req.q = request.q;
  req.on_scored = request.on_scored;
  const ArmConfig q = request.q;
  req.reach = reach_filter(arm.workspace, request.base, [q] { return q; }, arm.checker);
  req.in_workspace = [&workspace = arm.workspace, base = request.base](const Vec3& p) {
    return workspace.in_workspace(base, p);
  };
  req.goal_free = [&model = arm.model, checker = arm.checker, base = request.base, q](const nbv::PlannedView& v) {
    return has_free_goal(model, checker, v, base, q);
  };
  NextViews out;
  out.batch = planner.next(req);
  if (request.failed) {
    std::vector<nbv::PlannedView>& views = out.batch.views;
    const auto kept = std::remove_if(views.begin(), views.end(), [&](const nbv::PlannedView& v) {
      return request.failed->contains(v.T_world_camera);
    });
    out.guarded = static_cast<std::size_t>(views.end() - kept);
    views.erase(kept, views.end());
  }
  if (request.max_views > 0 && out.batch.views.size() > request.max_views) out.batch.views.resize(request.max_views);
  if (out.batch.views.empty()) return out;
  if (out.batch.order == nbv::BatchOrder::kTour)
    out.ordered = tour_order(arm.model, arm.tour, request.base, request.q, out.batch.views, &out.unreachable);
  else
    out.ordered = out.batch.views;
  return out;
}

NextViews plan_next_views(const mapping::SemanticOcTree& map, nbv::ViewPlanner& planner, const RobotModel& model,
                          const MotionConfig& config, const NextViewsRequest& request) {
  const double resolution = map.params().resolution_m;
  std::shared_ptr<CollisionEnvironment> env = CollisionEnvironment::empty(resolution);
  env->update(occupied_voxel_centres(map), {});
  // Where the robot is cannot be an obstacle (as in the mission before each plan).
  const std::size_t cleared =
      env->clear_robot_volume(model, request.base, request.q, config.collision.environment_padding_m);
  // Views are kept when their IK is free with the goals' self clearance (ArmPlanner's goal test).
  const CollisionChecker checker(model, goal_collision_params(config.collision, config.planner), env);
  const WorkspaceFilter workspace(model, config.workspace);
  nbv::VoxelIndex index;
  NextViews out = next_views(map, index, planner, StopArm{model, workspace, &checker, config.tour}, request);
  out.cleared_voxels = cleared;
  return out;
}

}  // namespace canopy::motion
