#include "canopy/motion/arm_planner.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <utility>

#include "arm_search.h"
#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/common/timer.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {

namespace {

bool finite(const ArmConfig& q) {
  for (double v : q)
    if (!std::isfinite(v)) return false;
  return true;
}

std::string config_text(const ArmConfig& q) {
  std::string s = "[";
  for (int i = 0; i < kArmDof; ++i) s += (i ? ", " : "") + std::to_string(q[i]);
  return s + "]";
}

// A plan's early end: its status and one line saying why.
struct PlanFailure {
  PlanStatus status;
  std::string message;
};

// A measured start may overshoot a limit slightly (a goal at the limit, servo error): within
// `tol` of a limit it is moved onto it.
ArmConfig start_within_limits(const ArmConfig& start_in, const ArmLimits& limits, double tol) {
  ArmConfig start = start_in;
  for (int i = 0; i < kArmDof; ++i) {
    if (start[i] < limits.lower[i] && start[i] >= limits.lower[i] - tol) start[i] = limits.lower[i];
    if (start[i] > limits.upper[i] && start[i] <= limits.upper[i] + tol) start[i] = limits.upper[i];
  }
  return start;
}

// Why a plan from `start` to `goals` cannot start: a base pose not finite, a start or goal not
// finite or outside the joint limits, no goal, or the base or (check_start) the start in collision.
std::optional<PlanFailure> request_failure(const CollisionChecker& checker, const BasePose& base,
                                           const ArmConfig& start, const std::vector<ArmConfig>& goals,
                                           bool check_start) {
  const RobotModel& model = checker.model();
  if (!std::isfinite(base.x_m) || !std::isfinite(base.y_m) || !std::isfinite(base.yaw_rad))
    return PlanFailure{PlanStatus::kInvalidInput, "base pose is not finite"};
  if (!model.within_limits(start))
    return PlanFailure{PlanStatus::kInvalidInput,
                       "start configuration " + config_text(start) + " is not finite or outside the joint limits"};
  if (goals.empty()) return PlanFailure{PlanStatus::kInvalidInput, "no goal configuration given"};
  for (const ArmConfig& g : goals)
    if (!model.within_limits(g))
      return PlanFailure{PlanStatus::kInvalidInput,
                         "goal configuration " + config_text(g) + " is not finite or outside the joint limits"};

  if (checker.base_in_collision(base))
    return PlanFailure{PlanStatus::kStartInCollision, "the base itself is in collision with the map"};
  if (!check_start) return std::nullopt;
  const CollisionReport start_report = checker.report(base, start);
  if (start_report.in_collision)
    return PlanFailure{PlanStatus::kStartInCollision, "start state in collision: " + start_report.pairs.front()};
  return std::nullopt;
}

// The goals nearest `start` first, those in collision dropped, at most `max_goals`;
// `first_collision` names the first colliding goal's pair.
std::vector<ArmConfig> free_goals_nearest_first(const CollisionChecker& checker, const BasePose& base,
                                                const ArmConfig& start, const std::vector<ArmConfig>& goals_in,
                                                int max_goals, std::string* first_collision) {
  std::vector<ArmConfig> goals = goals_in;
  std::stable_sort(goals.begin(), goals.end(), [&](const ArmConfig& a, const ArmConfig& b) {
    return joint_distance(a, start) < joint_distance(b, start);
  });
  std::vector<ArmConfig> free_goals;
  for (const ArmConfig& g : goals) {
    const CollisionReport gr = checker.report(base, g);
    if (gr.in_collision) {
      if (first_collision->empty()) *first_collision = gr.pairs.front();
    } else if (static_cast<int>(free_goals.size()) < max_goals) {
      free_goals.push_back(g);
    }
  }
  return free_goals;
}

}  // namespace

CollisionParams goal_collision_params(const CollisionParams& collision, const PlannerParams& planner) {
  CollisionParams c = collision;
  c.self_padding_m += planner.goal_self_clearance_m;
  return c;
}

const char* to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::kSuccess: return "success";
    case PlanStatus::kNoIk: return "no_ik";
    case PlanStatus::kStartInCollision: return "start_in_collision";
    case PlanStatus::kGoalInCollision: return "goal_in_collision";
    case PlanStatus::kTimeout: return "timeout";
    case PlanStatus::kInvalidInput: return "invalid_input";
  }
  return "unknown";
}

ArmPlanner::ArmPlanner(const CollisionChecker& checker, const PlannerParams& params, const TrajectoryParams& trajectory)
    : checker_(&checker), params_(params), trajectory_params_(trajectory) {
  params_.validate();
  trajectory_params_.validate();
  if (params_.goal_self_clearance_m > 0.0)
    goal_checker_ = std::make_shared<const CollisionChecker>(
        checker.model(), goal_collision_params(checker.params(), params_), checker.environment());
  // OMPL reports every solve at INFO level; warnings and errors still show.
  quiet_ompl_info();
}

bool ArmPlanner::motion_valid(const BasePose& base, const ArmConfig& a, const ArmConfig& b) const {
  const int n = static_cast<int>(std::ceil(joint_distance(a, b) / params_.motion_check_resolution_rad));
  for (int k = 1; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = a[i] + s * (b[i] - a[i]);
    if (checker_->in_collision(base, q, BodySet::kArmOnly)) return false;
  }
  return true;
}

bool ArmPlanner::leaves_collision(const BasePose& base, const ArmConfig& a, const ArmConfig& b) const {
  const CollisionReport at_start = checker_->report(base, a);
  const std::set<std::string> touching(at_start.pairs.begin(), at_start.pairs.end());
  const int n = std::max(1, static_cast<int>(std::ceil(joint_distance(a, b) / params_.motion_check_resolution_rad)));
  bool out = !at_start.in_collision;
  for (int k = 1; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = a[i] + s * (b[i] - a[i]);
    const CollisionReport r = checker_->report(base, q);
    if (!r.in_collision) {
      out = true;
      continue;
    }
    if (out) return false;  // back into a collision after leaving it
    for (const std::string& pair : r.pairs)
      if (!touching.count(pair)) return false;  // a new contact on the way out
  }
  return out;
}

StartRepair ArmPlanner::repair_start(const BasePose& base, const ArmConfig& start, std::uint64_t seed) const {
  StartRepair rep;
  const CollisionReport at_start = checker_->report(base, start);
  if (!at_start.in_collision) return rep;
  rep.needed = true;
  rep.collision = at_start.pairs.front();
  if (checker_->base_in_collision(base)) return rep;  // moving the arm cannot help
  // A repaired state keeps the goals' clearance, so that the servos settling it do not touch again.
  const CollisionChecker& free_test = goal_checker_ ? *goal_checker_ : *checker_;
  const RobotModel& model = checker_->model();
  const ArmLimits& lim = model.limits();
  Rng rng(mix_seed(seed, 4));
  const int attempts = params_.repair_attempts;
  for (int k = 0; k < attempts; ++k) {
    // The jiggle grows from a small fraction of each joint's range to jiggle_fraction, so the
    // nearest repairs are found first.
    const double f = params_.jiggle_fraction * (k + 1) / attempts;
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i)
      q[i] = std::clamp(start[i] + f * (lim.upper[i] - lim.lower[i]) * rng.uniform(-1.0, 1.0), lim.lower[i], lim.upper[i]);
    ++rep.samples;
    if (free_test.in_collision(base, q) || !leaves_collision(base, start, q)) continue;
    rep.ok = true;
    rep.q = q;
    rep.how = "jiggle";
    return rep;
  }
  const ArmConfig& home = model.config().home;
  if (model.within_limits(home) && !free_test.in_collision(base, home) && leaves_collision(base, start, home)) {
    rep.ok = true;
    rep.q = home;
    rep.how = "home";
  }
  return rep;
}

ArmTrajectory ArmPlanner::repair_trajectory(const PlanResult& plan) const {
  if (plan.repair.size() < 2) return ArmTrajectory();
  return ArmTrajectory::time_parameterize(plan.repair, checker_->model().limits(), trajectory_params_);
}

PlanResult ArmPlanner::plan_to_camera_pose(const BasePose& base, const ArmConfig& start, const Pose& T_world_camera,
                                           std::uint64_t seed) const {
  const Stopwatch watch;
  PlanResult r;
  if (!T_world_camera.matrix().allFinite()) {
    r.status = PlanStatus::kInvalidInput;
    r.message = "goal camera pose is not finite";
    return r;
  }
  if (!finite(start)) {
    r.status = PlanStatus::kInvalidInput;
    r.message = "start configuration " + config_text(start) + " is not finite";
    return r;
  }
  const IkResult ik = checker_->model().camera_ik(base, T_world_camera, start);
  if (ik.empty()) {
    r.status = PlanStatus::kNoIk;
    const Vec3 p = T_world_camera.translation();
    r.message = "no IK solution within the joint limits for the camera at (" + std::to_string(p.x()) + ", " +
                std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")";
    r.planning_time_s = watch.seconds();
    return r;
  }
  std::vector<ArmConfig> goals(ik.q.begin(), ik.q.begin() + ik.count);
  r = plan_to_configs(base, start, goals, seed);
  r.planning_time_s = watch.seconds();
  return r;
}

PlanResult ArmPlanner::plan_to_configs(const BasePose& base, const ArmConfig& start, const std::vector<ArmConfig>& goals,
                                       std::uint64_t seed) const {
  return plan(base, start, goals, seed, /*search=*/true);
}

std::optional<PlanResult> ArmPlanner::straight_plan(const BasePose& base, const ArmConfig& start,
                                                    const std::vector<ArmConfig>& goals, std::uint64_t seed) const {
  PlanResult r = plan(base, start, goals, seed, /*search=*/false);
  if (!r.ok()) return std::nullopt;
  return r;
}

PlanResult ArmPlanner::plan(const BasePose& base, const ArmConfig& start_in, const std::vector<ArmConfig>& goals_in,
                            std::uint64_t seed, bool search) const {
  const Stopwatch watch;
  PlanResult r;
  auto fail = [&](PlanStatus s, std::string msg) {
    r.status = s;
    r.message = std::move(msg);
    r.planning_time_s = watch.seconds();
    return r;
  };
  const RobotModel& model = checker_->model();
  const ArmConfig measured = start_within_limits(start_in, model.limits(), params_.start_limit_tolerance_rad);
  if (const std::optional<PlanFailure> failure =
          request_failure(*checker_, base, measured, goals_in, /*check_start=*/!params_.repair_start))
    return fail(failure->status, failure->message);
  // A start in collision is left first (repair_start): the plan starts at the repaired state.
  ArmConfig start = measured;
  if (params_.repair_start) {
    const StartRepair rep = repair_start(base, measured, seed);
    if (rep.needed && !rep.ok)
      return fail(PlanStatus::kStartInCollision,
                  "start state in collision: " + rep.collision + "; no repair (" + std::to_string(rep.samples) +
                      " nearby states sampled, home not reachable by a straight move)");
    if (rep.needed) {
      r.repaired = true;
      r.repair = {measured, rep.q};
      r.repair_note = rep.collision + ", left by " + rep.how;
      start = rep.q;
    }
  }
  std::string goal_collision;
  const std::vector<ArmConfig> free_goals = free_goals_nearest_first(
      goal_checker_ ? *goal_checker_ : *checker_, base, start, goals_in, params_.max_goal_configs, &goal_collision);
  if (free_goals.empty())
    return fail(PlanStatus::kGoalInCollision, "every goal configuration is in collision (first: " + goal_collision + ")");

  auto succeed = [&](std::vector<ArmConfig> path, bool direct) {
    if (r.repaired) path.insert(path.begin(), measured);  // the repair move first
    r.status = PlanStatus::kSuccess;
    r.path = std::move(path);
    r.goal = r.path.back();
    r.direct = direct;
    r.trajectory = ArmTrajectory::time_parameterize(r.path, model.limits(), trajectory_params_);
    r.planning_time_s = watch.seconds();
    return r;
  };

  if (params_.try_direct_first) {
    for (const ArmConfig& g : free_goals)
      if (motion_valid(base, start, g)) return succeed({start, g}, true);
  }

  if (!search) return fail(PlanStatus::kTimeout, "no straight line to a goal (search not asked for)");
  SearchOutcome found = search_path(*checker_, params_, base, start, free_goals, seed, watch);
  if (found.no_time) return fail(PlanStatus::kTimeout, "time limit used up before planning started");
  r.iterations = found.iterations;
  if (!found.solved)
    return fail(PlanStatus::kTimeout,
                found.timed_out ? "no path within the " + std::to_string(params_.time_limit_s) + " s safety limit (" +
                                      found.status + ")"
                                : "no path within " + std::to_string(params_.max_iterations) +
                                      " planner iterations (" + found.status + ")");
  std::vector<ArmConfig> path = std::move(found.path);
  // Defensive re-check with our own interpolation: what the robot executes must be free.
  for (size_t k = 1; k < path.size(); ++k)
    if (!motion_valid(base, path[k - 1], path[k]))
      return fail(PlanStatus::kTimeout, "planner returned a path segment in collision");
  return succeed(std::move(path), false);
}

}  // namespace canopy::motion
