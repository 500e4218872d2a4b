#include "canopy/motion/arm_planner.h"

#include <ompl/base/goals/GoalStates.h>
#include <ompl/base/DiscreteMotionValidator.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/est/BiEST.h>
#include <ompl/geometric/planners/est/EST.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/kpiece/BKPIECE1.h>
#include <ompl/geometric/planners/kpiece/KPIECE1.h>
#include <ompl/geometric/planners/kpiece/LBKPIECE1.h>
#include <ompl/geometric/planners/prm/LazyPRM.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/rrt/BiTRRT.h>
#include <ompl/geometric/planners/rrt/LazyRRT.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/geometric/planners/sbl/SBL.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <algorithm>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/common/timer.h"
#include "canopy/common/yaml_reader.h"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace canopy::motion {

namespace {

// Per-plan determinism: every random stream a plan draws from is seeded from the request's
// seed (OMPL's process-wide seed only decides streams we do not reach, see planner_registry).
std::uint_fast32_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  const std::uint64_t z = mix_seed(seed, stream);
  return static_cast<std::uint_fast32_t>((z >> 32) ^ (z & 0xffffffffULL)) | 1u;  // OMPL rejects 0
}

// Uniform joint-space samples from a seeded stream.
class SeededSampler : public ob::RealVectorStateSampler {
 public:
  SeededSampler(const ob::StateSpace* space, std::uint_fast32_t seed) : ob::RealVectorStateSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

// A planner whose own random stream (goal bias, tree choices) is seeded.
template <typename P>
class Seeded : public P {
 public:
  Seeded(const ob::SpaceInformationPtr& si, std::uint_fast32_t seed) : P(si) { this->rng_.setLocalSeed(seed); }
};

// A path simplifier with a seeded shortcut stream.
class SeededSimplifier : public og::PathSimplifier {
 public:
  SeededSimplifier(const ob::SpaceInformationPtr& si, std::uint_fast32_t seed) : og::PathSimplifier(si) {
    rng_.setLocalSeed(seed);
  }
};

using PlannerFactory = std::function<ob::PlannerPtr(const ob::SpaceInformationPtr&, double range, std::uint_fast32_t seed)>;

template <typename P>
PlannerFactory with_range() {
  return [](const ob::SpaceInformationPtr& si, double range, std::uint_fast32_t seed) {
    auto p = std::make_shared<Seeded<P>>(si, seed);
    if (range > 0.0) p->setRange(range);
    return ob::PlannerPtr(p);
  };
}

// Planners without a random stream of their own that we can reach (they sample through the
// seeded state sampler; any other internal stream follows OMPL's process seed).
template <typename P>
PlannerFactory unseeded_with_range() {
  return [](const ob::SpaceInformationPtr& si, double range, std::uint_fast32_t) {
    auto p = std::make_shared<P>(si);
    if (range > 0.0) p->setRange(range);
    return ob::PlannerPtr(p);
  };
}

template <typename P>
PlannerFactory plain() {
  return [](const ob::SpaceInformationPtr& si, double, std::uint_fast32_t seed) {
    return ob::PlannerPtr(std::make_shared<Seeded<P>>(si, seed));
  };
}

template <typename P>
PlannerFactory unseeded_plain() {
  return [](const ob::SpaceInformationPtr& si, double, std::uint_fast32_t) { return ob::PlannerPtr(std::make_shared<P>(si)); };
}

// The planner registry: one place that maps names to OMPL planners (STYLE.md).
const std::map<std::string, PlannerFactory>& planner_registry() {
  static const std::map<std::string, PlannerFactory> registry = {
      {"RRTConnect", with_range<og::RRTConnect>()}, {"RRT", with_range<og::RRT>()},
      {"RRTstar", with_range<og::RRTstar>()},       {"BiTRRT", unseeded_with_range<og::BiTRRT>()},
      {"LazyRRT", with_range<og::LazyRRT>()},       {"KPIECE1", with_range<og::KPIECE1>()},
      {"BKPIECE1", with_range<og::BKPIECE1>()},     {"LBKPIECE1", with_range<og::LBKPIECE1>()},
      {"EST", with_range<og::EST>()},               {"BiEST", with_range<og::BiEST>()},
      {"SBL", with_range<og::SBL>()},               {"PRM", plain<og::PRM>()},
      {"LazyPRM", unseeded_with_range<og::LazyPRM>()}, {"BITstar", unseeded_plain<og::BITstar>()},
  };
  return registry;
}

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

// OMPL's DiscreteMotionValidator's verdicts, the states of a long motion tested on all cores:
// a motion is valid when its end and every state at k / n of the way are valid (n the motion's
// valid-segment count, k = 1 .. n - 1), which does not depend on the order they are tested in.
// Each thread takes every t-th state of OMPL's bisection order and all stop at the first
// invalid one. Short motions, and the variant that reports the last valid state (whose answer
// does depend on the order), are OMPL's own.
class SharedMotionValidator : public ob::MotionValidator {
 public:
  SharedMotionValidator(const ob::SpaceInformationPtr& si, int threads)
      : ob::MotionValidator(si), serial_(si), threads_(threads) {}

  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    const ob::StateSpacePtr& space = si_->getStateSpace();
    const int n = space->validSegmentCount(s1, s2);
    if (n < kSharedSegments) return count(serial_.checkMotion(s1, s2));
    if (!si_->isValid(s2)) return count(false);
    const std::vector<int> order = bisection_order(n);
    std::atomic<bool> invalid{false};
    auto test = [&](int first) {
      ob::State* s = si_->allocState();
      for (std::size_t i = std::size_t(first); i < order.size() && !invalid.load(std::memory_order_relaxed);
           i += std::size_t(threads_)) {
        space->interpolate(s1, s2, double(order[i]) / double(n), s);
        if (!si_->isValid(s)) invalid.store(true, std::memory_order_relaxed);
      }
      si_->freeState(s);
    };
    tbb::task_group group;
    for (int t = 1; t < threads_; ++t) group.run([&test, t] { test(t); });
    test(0);
    group.wait();
    return count(!invalid.load());
  }

  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last_valid) const override {
    return count(serial_.checkMotion(s1, s2, last_valid));
  }

 private:
  // Motions of fewer segments are tested on the calling thread (waking a worker costs about
  // what a few state tests do).
  static constexpr int kSharedSegments = 16;

  // The states 1 .. n - 1 in the order OMPL's DiscreteMotionValidator tests them: the middle of
  // the motion first, then the middles of its halves, breadth first (the spans are the queue,
  // read from its front as it grows; two allocations against n collision tests).
  static std::vector<int> bisection_order(int n) {
    std::vector<int> order;
    std::vector<std::pair<int, int>> spans{{1, n - 1}};
    order.reserve(std::size_t(n));
    spans.reserve(std::size_t(n));
    for (std::size_t k = 0; k < spans.size(); ++k) {
      const auto [lo, hi] = spans[k];
      const int mid = (lo + hi) / 2;
      order.push_back(mid);
      if (lo < mid) spans.emplace_back(lo, mid - 1);
      if (mid < hi) spans.emplace_back(mid + 1, hi);
    }
    return order;
  }

  bool count(bool valid) const {
    valid ? ++valid_ : ++invalid_;
    return valid;
  }

  ob::DiscreteMotionValidator serial_;
  int threads_;
};

// OMPL's view of the arm at `base`: the 6-D joint space bounded by the planning limits, its
// sampler's stream seeded from `seed`, states valid when the arm is free, motions tested at the
// parameters' resolution on their motion-check threads.
ob::SpaceInformationPtr make_space_information(const CollisionChecker& checker_ref, const PlannerParams& params,
                                               const BasePose& base, std::uint64_t seed) {
  const ArmLimits& lim = checker_ref.model().limits();
  auto space = std::make_shared<ob::RealVectorStateSpace>(kArmDof);
  const std::uint_fast32_t sampler_seed = stream_seed(seed, 1);
  space->setStateSamplerAllocator([sampler_seed](const ob::StateSpace* s) -> ob::StateSamplerPtr {
    return std::make_shared<SeededSampler>(s, sampler_seed);
  });
  ob::RealVectorBounds bounds(kArmDof);
  for (int i = 0; i < kArmDof; ++i) {
    bounds.setLow(static_cast<unsigned>(i), lim.lower[i]);
    bounds.setHigh(static_cast<unsigned>(i), lim.upper[i]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  const CollisionChecker* checker = &checker_ref;
  si->setStateValidityChecker([checker, base, space](const ob::State* s) {
    if (!space->satisfiesBounds(s)) return false;
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = v->values[i];
    return !checker->in_collision(base, q, BodySet::kArmOnly);
  });
  // A fixed joint-space resolution: OMPL takes it as a fraction of the space's extent.
  si->setStateValidityCheckingResolution(params.motion_check_resolution_rad / space->getMaximumExtent());
  const int available = std::max(1, tbb::this_task_arena::max_concurrency());
  const int threads = params.motion_check_threads == 0 ? available : std::min(params.motion_check_threads, available);
  if (threads > 1) si->setMotionValidator(std::make_shared<SharedMotionValidator>(si, threads));
  return si;
}

// OMPL's problem: the arm's space information, the start, the goals and the parameters'
// planner, its streams seeded from `seed`.
std::unique_ptr<og::SimpleSetup> make_setup(const CollisionChecker& checker_ref, const PlannerParams& params,
                                            const BasePose& base, const ArmConfig& start,
                                            const std::vector<ArmConfig>& free_goals, std::uint64_t seed) {
  auto ss = std::make_unique<og::SimpleSetup>(make_space_information(checker_ref, params, base, seed));
  const ob::StateSpacePtr& space = ss->getStateSpace();
  ob::ScopedState<> start_state(space);
  for (int i = 0; i < kArmDof; ++i) start_state[static_cast<unsigned>(i)] = start[i];
  ss->setStartState(start_state);
  auto goal_states = std::make_shared<ob::GoalStates>(ss->getSpaceInformation());
  for (const ArmConfig& g : free_goals) {
    ob::ScopedState<> gs(space);
    for (int i = 0; i < kArmDof; ++i) gs[static_cast<unsigned>(i)] = g[i];
    goal_states->addState(gs);
  }
  ss->setGoal(goal_states);
  ss->setPlanner(planner_registry().at(params.planner)(ss->getSpaceInformation(), params.range_rad, stream_seed(seed, 2)));
  ss->setup();
  return ss;
}

// Solves within `max_iterations` planner iterations: the termination condition is polled once
// per iteration, so a seed gives the same path however loaded the machine is; the wall clock
// limit `remaining_s` is only a safety net (`timed_out` says it ended the search). `used` gets
// the iterations the search ran (polls answered "go on"), at most max_iterations.
ob::PlannerStatus solve_within_budget(og::SimpleSetup& ss, int max_iterations, double remaining_s, bool* timed_out,
                                      int* used) {
  int iterations = 0;
  const ob::PlannerTerminationCondition budget([&iterations, max_iterations] { return ++iterations > max_iterations; });
  const ob::PlannerTerminationCondition clock = ob::timedPlannerTerminationCondition(remaining_s);
  const ob::PlannerTerminationCondition ptc([&] {
    if (budget()) return true;
    if (clock()) return *timed_out = true;
    return false;
  });
  const ob::PlannerStatus status = ss.solve(ptc);
  *used = *timed_out ? iterations - 1 : std::min(iterations, max_iterations);  // the clock's poll ran none
  return status;
}

// The solution path's states as joint configurations.
std::vector<ArmConfig> solution_configs(og::SimpleSetup& ss) {
  og::PathGeometric& p = ss.getSolutionPath();
  std::vector<ArmConfig> path;
  for (size_t k = 0; k < p.getStateCount(); ++k) {
    const auto* v = p.getState(static_cast<unsigned>(k))->as<ob::RealVectorStateSpace::StateType>();
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = v->values[i];
    path.push_back(q);
  }
  return path;
}

}  // namespace

bool planner_checks_motion(const CollisionChecker& checker, const PlannerParams& params, const BasePose& base,
                           const ArmConfig& a, const ArmConfig& b) {
  params.validate();
  const ob::SpaceInformationPtr si = make_space_information(checker, params, base, 0);
  si->setup();
  ob::ScopedState<> sa(si), sb(si);
  for (int i = 0; i < kArmDof; ++i) {
    sa[static_cast<unsigned>(i)] = a[i];
    sb[static_cast<unsigned>(i)] = b[i];
  }
  return si->checkMotion(sa.get(), sb.get());
}

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

std::vector<std::string> planner_names() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : planner_registry()) names.push_back(name);
  return names;
}

bool seed_planner_rng(std::uint64_t seed) {
  static std::once_flag once;
  bool applied = false;
  std::call_once(once, [&] {
    ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(seed));
    applied = true;
  });
  return applied;
}

ArmPlanner::ArmPlanner(const CollisionChecker& checker, const PlannerParams& params, const TrajectoryParams& trajectory)
    : checker_(&checker), params_(params), trajectory_params_(trajectory) {
  params_.validate();
  trajectory_params_.validate();
  if (params_.goal_self_clearance_m > 0.0)
    goal_checker_ = std::make_shared<const CollisionChecker>(
        checker.model(), goal_collision_params(checker.params(), params_), checker.environment());
  // OMPL reports every solve at INFO level; warnings and errors still show.
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
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
  const std::unique_ptr<og::SimpleSetup> ss = make_setup(*checker_, params_, base, start, free_goals, seed);
  const double remaining = params_.time_limit_s - watch.seconds();
  if (remaining <= 0.0) return fail(PlanStatus::kTimeout, "time limit used up before planning started");
  bool timed_out = false;
  const ob::PlannerStatus solved =
      solve_within_budget(*ss, params_.max_iterations, remaining, &timed_out, &r.iterations);
  if (solved != ob::PlannerStatus::EXACT_SOLUTION)
    return fail(PlanStatus::kTimeout,
                timed_out ? "no path within the " + std::to_string(params_.time_limit_s) + " s safety limit (" +
                                solved.asString() + ")"
                          : "no path within " + std::to_string(params_.max_iterations) + " planner iterations (" +
                                solved.asString() + ")");
  if (params_.simplify) {
    SeededSimplifier simplifier(ss->getSpaceInformation(), stream_seed(seed, 3));
    simplifier.simplifyMax(ss->getSolutionPath());
  }
  std::vector<ArmConfig> path = solution_configs(*ss);
  // Defensive re-check with our own interpolation: what the robot executes must be free.
  for (size_t k = 1; k < path.size(); ++k)
    if (!motion_valid(base, path[k - 1], path[k]))
      return fail(PlanStatus::kTimeout, "planner returned a path segment in collision");
  return succeed(std::move(path), false);
}

}  // namespace canopy::motion
