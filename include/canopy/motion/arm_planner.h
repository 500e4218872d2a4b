#pragma once
// Collision-free arm motion in joint space with OMPL (RRTConnect by default): the FCL
// checker validates states, motions are checked at a fixed joint-space resolution, the
// path is simplified and timed within the joint limits. Expected failures (no IK, start or
// goal in collision, timeout, bad input) come back as a status with a message.
// OMPL stays inside arm_planner.cpp.

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/common/types.h"
#include "canopy/motion/collision.h"
#include "canopy/motion/robot_model.h"
#include "canopy/motion/trajectory.h"

namespace canopy {
class YamlReader;
}

namespace canopy::motion {

/// Outcome of a planning request.
enum class PlanStatus {
  kSuccess,
  kNoIk,              ///< The camera pose has no IK solution within the joint limits.
  kStartInCollision,  ///< The start state (or the base itself) is in collision.
  kGoalInCollision,   ///< Every IK solution of the goal is in collision.
  kTimeout,           ///< No path found within the time limit.
  kInvalidInput,      ///< Non-finite or out-of-limit input.
};
const char* to_string(PlanStatus status);

/// Planner settings (configs/motion.yaml, section "planner").
struct PlannerParams {
  std::string planner = "RRTConnect";      ///< A name from planner_names().
  /// Planner iterations per request: the budget that decides, so results do not depend on load.
  int max_iterations = 20000;
  double time_limit_s = 10.0;              ///< Wall-clock safety net per request.
  double motion_check_resolution_rad = 0.02;  ///< Joint-space (Euclidean) step of motion checks.
  double range_rad = 0.0;                  ///< Tree extension step; 0: the planner's default.
  bool try_direct_first = true;            ///< Try the straight joint-space line before OMPL.
  bool simplify = true;                    ///< Shortcut the path (deterministic, to convergence).
  int max_goal_configs = 8;                ///< IK solutions handed to the planner as goals.
  /// A start up to this far outside the joint limits (servo overshoot at a limit) is
  /// clamped into them; further out it is invalid input.
  double start_limit_tolerance_rad = 0.01;

  template <class A>
  void visit(A& a);
  void validate() const { validate_params(*this, "planner"); }
};

/// Names accepted by PlannerParams::planner.
std::vector<std::string> planner_names();

template <class A>
void PlannerParams::visit(A& a) {
  a.one_of("planner", planner, planner_names(), "OMPL planner");
  a("max_iterations", max_iterations, limits::at_least(1), "Planner iterations per request (the budget that decides)");
  a("time_limit_s", time_limit_s, limits::positive(), "Wall-clock safety net per request [s]");
  a("motion_check_resolution_rad", motion_check_resolution_rad, limits::positive(),
    "Joint-space step of motion checks [rad]");
  a("range_rad", range_rad, limits::non_negative(), "Tree extension step; 0 = the planner's default [rad]");
  a("try_direct_first", try_direct_first, "Try the straight joint-space line before OMPL");
  a("simplify", simplify, "Shortcut the path (deterministic, to convergence)");
  a("max_goal_configs", max_goal_configs, limits::in(1, 8), "IK solutions handed to the planner as goals");
  a("start_limit_tolerance_rad", start_limit_tolerance_rad, limits::non_negative(),
    "A start this far outside the joint limits is clamped into them [rad]");
}

/// Sets OMPL's global seed; effective only before the first planner runs in the process
/// (OMPL's rule). Returns false when it was already set (to any value) in this process.
/// Plans are seeded per request (ArmPlanner's `seed` arguments); this covers only the
/// streams that are out of reach (see plan_to_configs).
bool seed_planner_rng(std::uint64_t seed);

/// Result of a planning request.
struct PlanResult {
  PlanStatus status = PlanStatus::kInvalidInput;
  std::string message;
  std::vector<ArmConfig> path;  ///< Collision-checked waypoints, start first (on success).
  ArmTrajectory trajectory;     ///< Timed path (on success).
  ArmConfig goal{};             ///< The goal configuration reached (on success).
  double planning_time_s = 0.0;
  bool direct = false;          ///< The straight line was valid; OMPL was not needed.
  bool ok() const { return status == PlanStatus::kSuccess; }
};

/// Plans arm motions for a robot model in the environment of a collision checker, with the
/// base fixed. Queries are const; run one at a time per process for reproducible results.
class ArmPlanner {
 public:
  ArmPlanner(const CollisionChecker& checker, const PlannerParams& params,
             const TrajectoryParams& trajectory = TrajectoryParams{});

  /// Plans from `start` to one of `goals` (tried nearest first).
  /// `seed` seeds every random stream of this request: the same request and seed give the
  /// same path (RRTConnect, RRT, RRTstar, LazyRRT, KPIECE1, BKPIECE1, LBKPIECE1, EST, BiEST,
  /// SBL, PRM; BiTRRT, LazyPRM and BITstar sample through the seeded sampler only).
  PlanResult plan_to_configs(const BasePose& base, const ArmConfig& start, const std::vector<ArmConfig>& goals,
                             std::uint64_t seed = 1) const;
  /// Plans from `start` until the camera is at T_world_camera (IK solutions as goals).
  PlanResult plan_to_camera_pose(const BasePose& base, const ArmConfig& start, const Pose& T_world_camera,
                                 std::uint64_t seed = 1) const;
  /// True when the straight joint-space line a -> b is collision-free at the resolution.
  bool motion_valid(const BasePose& base, const ArmConfig& a, const ArmConfig& b) const;

  const PlannerParams& params() const { return params_; }
  const CollisionChecker& checker() const { return *checker_; }

 private:
  const CollisionChecker* checker_;
  PlannerParams params_;
  TrajectoryParams trajectory_params_;
};

}  // namespace canopy::motion
