#pragma once
// Collision-free arm motion in joint space with OMPL (RRTConnect by default): the FCL
// checker validates states, motions are checked at a fixed joint-space resolution, the
// path is simplified and timed within the joint limits. Expected failures (no IK, start or
// goal in collision, timeout, bad input) come back as a status with a message.
// OMPL stays inside src/motion/arm_search.cpp.

#include <cstdint>
#include <memory>
#include <optional>
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
  int max_iterations = 3000;
  double time_limit_s = 10.0;              ///< Wall-clock safety net per request.
  double motion_check_resolution_rad = 0.02;  ///< Joint-space (Euclidean) step of motion checks.
  /// Threads testing the states of one long motion (0: all cores, 1: the planning thread
  /// alone). The verdicts, hence the plans, are the same for any number.
  int motion_check_threads = 0;
  double range_rad = 0.0;                  ///< Tree extension step; 0: the planner's default.
  bool try_direct_first = true;            ///< Try the straight joint-space line before OMPL.
  bool simplify = true;                    ///< Shortcut the path (deterministic, to convergence).
  int max_goal_configs = 8;                ///< IK solutions handed to the planner as goals.
  /// A start up to this far outside the joint limits (servo overshoot at a limit) is
  /// clamped into them; further out it is invalid input.
  double start_limit_tolerance_rad = 0.01;
  /// A start in collision (with itself or the map; not the base) is repaired, not refused:
  /// nearby states are sampled (each joint within a growing fraction of its range, up to
  /// jiggle_fraction) and the first valid one that a short straight move reaches without a
  /// new contact is taken; else the home configuration by the same test (MoveIt's
  /// FixStartStateCollision, docs/mission.md). The repair move is the plan's first segment.
  bool repair_start = true;
  double jiggle_fraction = 0.02;  ///< Largest jiggle, as a fraction of each joint's range.
  int repair_attempts = 100;      ///< States sampled at most before the retreat home.
  /// Goals must keep this clearance from the robot's own shapes (self-collision padding of the
  /// goal test only): the servos settle a goal within about 1 mm and MuJoCo's soft contacts
  /// let touching shapes press into each other, so a goal touching the robot ends in
  /// self-collision and the next plan's start with it (docs/motion.md).
  double goal_self_clearance_m = 0.001;

  template <class A>
  void visit(A& a);
  void validate() const { validate_params(*this, "planner"); }
};

/// The collision settings goals are checked with: `collision` with the self padding raised by
/// planner.goal_self_clearance_m (ArmPlanner's goal test; the view planners' reachability
/// filter uses the same, so that a view it keeps is not refused at planning).
CollisionParams goal_collision_params(const CollisionParams& collision, const PlannerParams& planner);

/// The planner's verdict on the straight joint-space motion a -> b of the arm at `base` (the
/// arm alone against the map, as the planner tests states): OMPL's discrete motion check at
/// params.motion_check_resolution_rad (b and every state at k / n of the way, n the motion's
/// valid-segment count), its states tested on params.motion_check_threads threads. `a` is
/// taken as valid.
bool planner_checks_motion(const CollisionChecker& checker, const PlannerParams& params, const BasePose& base,
                           const ArmConfig& a, const ArmConfig& b);

/// Names accepted by PlannerParams::planner.
std::vector<std::string> planner_names();

template <class A>
void PlannerParams::visit(A& a) {
  a.one_of("planner", planner, planner_names(), "OMPL planner");
  a("max_iterations", max_iterations, limits::at_least(1), "Planner iterations per request (the budget that decides)");
  a("time_limit_s", time_limit_s, limits::positive(), "Wall-clock safety net per request [s]");
  a("motion_check_resolution_rad", motion_check_resolution_rad, limits::positive(),
    "Joint-space step of motion checks [rad]");
  a("motion_check_threads", motion_check_threads, limits::in(0, 256),
    "Threads testing one motion's states; 0 = all cores (the plans are the same)");
  a("range_rad", range_rad, limits::non_negative(), "Tree extension step; 0 = the planner's default [rad]");
  a("try_direct_first", try_direct_first, "Try the straight joint-space line before OMPL");
  a("simplify", simplify, "Shortcut the path (deterministic, to convergence)");
  a("max_goal_configs", max_goal_configs, limits::in(1, 8), "IK solutions handed to the planner as goals");
  a("start_limit_tolerance_rad", start_limit_tolerance_rad, limits::non_negative(),
    "A start this far outside the joint limits is clamped into them [rad]");
  a("repair_start", repair_start, "Repair a start in collision (jiggle, else home) instead of refusing it");
  a("jiggle_fraction", jiggle_fraction, limits::in(0.0, 0.5), "Largest start repair jiggle, fraction of each joint's range");
  a("repair_attempts", repair_attempts, limits::in(1, 100000), "States sampled at most by a start repair");
  a("goal_self_clearance_m", goal_self_clearance_m, limits::in(0.0, 0.1),
    "Goals keep this clearance from the robot's own shapes [m]");
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
  /// OMPL iterations this request used (0 when OMPL did not run: the straight line, or a
  /// failure before planning; max_iterations when the budget ran out). A request with the same
  /// seed and a budget of at least this many gives the same outcome (the budget is counted in
  /// these iterations), so a budget's effect can be read off from recorded requests.
  int iterations = 0;
  /// The start was in collision and was repaired: `repair` leads from it to a free state (the
  /// path's first segment on success; on failure a move of its own, see repair_trajectory).
  bool repaired = false;
  std::vector<ArmConfig> repair;  ///< {start, free state} when repaired.
  std::string repair_note;        ///< What was in collision and how it was left ("jiggle", "home").
  bool ok() const { return status == PlanStatus::kSuccess; }
};

/// How a start in collision is left (ArmPlanner::repair_start).
struct StartRepair {
  bool needed = false;        ///< The start was in collision.
  bool ok = false;            ///< A free state was found and the straight move to it is safe.
  ArmConfig q{};              ///< That state.
  std::string how;            ///< "jiggle" or "home".
  std::string collision;      ///< The start's first colliding pair.
  int samples = 0;            ///< States sampled.
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
  /// plan_to_configs' result when it is the straight line to a goal (`direct`), found without
  /// searching; nullopt when that request would search (OMPL) or fail. For a caller that keeps
  /// only a straight plan (the mission's overlapped moves), so no search is run and dropped.
  std::optional<PlanResult> straight_plan(const BasePose& base, const ArmConfig& start,
                                          const std::vector<ArmConfig>& goals, std::uint64_t seed = 1) const;
  /// Plans from `start` until the camera is at T_world_camera (IK solutions as goals).
  PlanResult plan_to_camera_pose(const BasePose& base, const ArmConfig& start, const Pose& T_world_camera,
                                 std::uint64_t seed = 1) const;
  /// True when the straight joint-space line a -> b is collision-free at the resolution.
  bool motion_valid(const BasePose& base, const ArmConfig& a, const ArmConfig& b) const;
  /// When `start` is in collision (self or map; the base must be free): a nearby free state
  /// reached by a straight joint move that leaves the collision and touches nothing new, else
  /// the home configuration by the same test. Deterministic for a seed.
  StartRepair repair_start(const BasePose& base, const ArmConfig& start, std::uint64_t seed = 1) const;
  /// The timed straight move of a repair (plan.repair), to leave the collision when the plan
  /// from the repaired state failed.
  ArmTrajectory repair_trajectory(const PlanResult& plan) const;

  const PlannerParams& params() const { return params_; }
  const CollisionChecker& checker() const { return *checker_; }
  /// The checker goals (and repaired starts) must be free in: checker() with the goals' self
  /// clearance (goal_collision_params).
  const CollisionChecker& goal_checker() const { return goal_checker_ ? *goal_checker_ : *checker_; }

 private:
  /// True when the straight move a -> b leaves a collision: states in collision come only
  /// first and collide in no pair the start does not; the end is free.
  bool leaves_collision(const BasePose& base, const ArmConfig& a, const ArmConfig& b) const;
  /// plan_to_configs; with `search` false it stops where OMPL would start (status kTimeout).
  PlanResult plan(const BasePose& base, const ArmConfig& start, const std::vector<ArmConfig>& goals,
                  std::uint64_t seed, bool search) const;

  const CollisionChecker* checker_;
  std::shared_ptr<const CollisionChecker> goal_checker_;  ///< Self padding goal_self_clearance_m added (null when 0).
  PlannerParams params_;
  TrajectoryParams trajectory_params_;
};

}  // namespace canopy::motion
