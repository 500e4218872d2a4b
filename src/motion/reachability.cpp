#include "canopy/motion/reachability.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/common/value_text.h"
#include "canopy/common/view_sphere.h"

namespace canopy::motion {

int ReachReport::count_ik() const {
  return static_cast<int>(std::count_if(samples.begin(), samples.end(), [](const ReachSample& s) { return s.ik; }));
}
int ReachReport::count_collision_free() const {
  return static_cast<int>(
      std::count_if(samples.begin(), samples.end(), [](const ReachSample& s) { return s.collision_free; }));
}
int ReachReport::count_workspace_kept() const {
  return static_cast<int>(
      std::count_if(samples.begin(), samples.end(), [](const ReachSample& s) { return s.workspace_kept; }));
}
int ReachReport::count_planned() const {
  return static_cast<int>(std::count_if(samples.begin(), samples.end(), [](const ReachSample& s) { return s.planned; }));
}
double ReachReport::fraction_ik() const { return samples.empty() ? 0.0 : double(count_ik()) / samples.size(); }
double ReachReport::fraction_collision_free() const {
  return samples.empty() ? 0.0 : double(count_collision_free()) / samples.size();
}
double ReachReport::fraction_planned() const { return samples.empty() ? 0.0 : double(count_planned()) / samples.size(); }

double ReachReport::median_planning_time_s() const {
  std::vector<double> t;
  for (const auto& s : samples)
    if (s.collision_free && s.planning_time_s > 0.0) t.push_back(s.planning_time_s);
  if (t.empty()) return 0.0;
  std::nth_element(t.begin(), t.begin() + static_cast<long>(t.size() / 2), t.end());
  return t[t.size() / 2];
}

nlohmann::json ReachReport::to_json(bool with_samples) const {
  nlohmann::json j;
  j["base"] = {base.x_m, base.y_m, base.yaw_rad};
  j["targets"] = targets;
  j["views"] = samples.size();
  j["ik_reachable"] = count_ik();
  j["collision_free"] = count_collision_free();
  j["workspace_kept"] = count_workspace_kept();
  j["planned"] = count_planned();
  j["fraction_ik_reachable"] = fraction_ik();
  j["fraction_collision_free"] = fraction_collision_free();
  j["fraction_planned"] = fraction_planned();
  j["median_planning_time_s"] = median_planning_time_s();
  if (with_samples) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& s : samples) {
      nlohmann::json e;
      e["target"] = {s.target.x(), s.target.y(), s.target.z()};
      e["camera"] = pose_to_json(s.T_world_camera);
      e["ik"] = s.ik;
      e["collision_free"] = s.collision_free;
      e["workspace_kept"] = s.workspace_kept;
      e["planned"] = s.planned;
      e["plan_status"] = s.collision_free ? to_string(s.plan_status) : "not_attempted";
      e["planning_time_s"] = s.planning_time_s;
      arr.push_back(e);
    }
    j["samples"] = arr;
  }
  return j;
}

ReachReport evaluate_reachability(const ArmPlanner& planner, const WorkspaceFilter* filter, const BasePose& base,
                                  const ArmConfig& start, const std::vector<Vec3>& targets, const ReachParams& params) {
  params.validate();
  const CollisionChecker& checker = planner.checker();
  const RobotModel& model = checker.model();
  ReachReport report;
  report.base = base;
  const Vec3 arm = (RobotModel::T_world_base(base) * model.T_base_arm()).translation();
  for (const Vec3& target : targets) {
    if (!target.allFinite() || (target - arm).head<2>().norm() > params.max_target_distance_m) continue;
    ++report.targets;
    for (const SphereView& v : sphere_views(target, params.sphere)) {
      const Pose& T = v.T_world_camera;
      ReachSample s;
      s.target = target;
      s.T_world_camera = T;
      const IkResult ik = model.camera_ik(base, T, start);
      s.ik = !ik.empty();
      for (int k = 0; k < ik.count && !s.collision_free; ++k)
        s.collision_free = !checker.in_collision(base, ik.q[static_cast<size_t>(k)]);
      if (filter) s.workspace_kept = filter->filter(base, T, start, &checker).kept();
      if (s.collision_free && params.plan) {
        const PlanResult r = planner.plan_to_camera_pose(base, start, T);
        s.planned = r.ok();
        s.plan_status = r.status;
        s.planning_time_s = r.planning_time_s;
      }
      report.samples.push_back(s);
    }
  }
  return report;
}

}  // namespace canopy::motion
