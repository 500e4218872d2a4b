#pragma once
// Reachability of camera views for a fixed base pose: a grid of camera poses (positions on
// spheres around target points, e.g. fruits, times viewing directions towards them) is
// classified as IK-reachable, collision-free and planned. `canopy reach` reports it, and
// regression tests pin the fractions so that a change that breaks reachability fails CI.
// The targets and the environment come from the caller (evaluation/truth_voxels.h gives the
// ground truth's for `canopy reach`).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/types.h"
#include "canopy/common/view_sphere.h"
#include "canopy/motion/arm_planner.h"
#include "canopy/motion/workspace_filter.h"

namespace canopy::motion {

/// The view grid (defaults: the paper's candidate sphere, docs/background/nbv_pipeline.md).
struct ReachParams {
  ViewSphere sphere;                   ///< The views around each target.
  double max_target_distance_m = 0.9;
  bool plan = true;

  template <class A>
  void visit(A& a) {
    sphere.visit(a);
    a("max_target_distance_m", max_target_distance_m, limits::positive(),
      "Targets farther (horizontally) from the arm base are skipped [m]");
    a("plan", plan, "Plan to every collision-free view (else IK and collision only)");
  }
  void validate() const { validate_params(*this, "reach"); }
};

/// One evaluated view.
struct ReachSample {
  Vec3 target = Vec3::Zero();
  Pose T_world_camera = Pose::Identity();
  bool ik = false;              ///< An IK solution within the joint limits exists.
  bool collision_free = false;  ///< One of them is collision-free.
  bool workspace_kept = false;  ///< The workspace filter keeps the view (possibly moved).
  bool planned = false;         ///< A path from the start was found.
  PlanStatus plan_status = PlanStatus::kNoIk;
  double planning_time_s = 0.0;
};

/// All views of one base pose.
struct ReachReport {
  BasePose base;
  int targets = 0;
  std::vector<ReachSample> samples;
  int count_ik() const;
  int count_collision_free() const;
  int count_workspace_kept() const;
  int count_planned() const;
  /// Fractions of all samples (0 when there is none).
  double fraction_ik() const;
  double fraction_collision_free() const;
  double fraction_planned() const;
  double median_planning_time_s() const;  ///< Over the views that were planned for.
  /// Summary (and, with `samples`, every view) as JSON.
  nlohmann::json to_json(bool samples) const;
};

/// Evaluates the view grid around `targets` (those within reach distance of the arm base)
/// with the base at `base` and the arm starting at `start`. The workspace filter, when
/// given, is evaluated alongside (it does not change the other counts).
ReachReport evaluate_reachability(const ArmPlanner& planner, const WorkspaceFilter* filter, const BasePose& base,
                                  const ArmConfig& start, const std::vector<Vec3>& targets,
                                  const ReachParams& params);

}  // namespace canopy::motion
