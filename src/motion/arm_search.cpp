#include "arm_search.h"

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

#include <algorithm>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>

#include "canopy/common/random.h"

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

void quiet_ompl_info() { ompl::msg::setLogLevel(ompl::msg::LOG_WARN); }

SearchOutcome search_path(const CollisionChecker& checker, const PlannerParams& params, const BasePose& base,
                          const ArmConfig& start, const std::vector<ArmConfig>& free_goals, std::uint64_t seed,
                          const Stopwatch& watch) {
  SearchOutcome out;
  const std::unique_ptr<og::SimpleSetup> ss = make_setup(checker, params, base, start, free_goals, seed);
  const double remaining = params.time_limit_s - watch.seconds();
  if (remaining <= 0.0) {
    out.no_time = true;
    return out;
  }
  const ob::PlannerStatus solved =
      solve_within_budget(*ss, params.max_iterations, remaining, &out.timed_out, &out.iterations);
  out.status = solved.asString();
  if (solved != ob::PlannerStatus::EXACT_SOLUTION) return out;
  out.solved = true;
  if (params.simplify) {
    SeededSimplifier simplifier(ss->getSpaceInformation(), stream_seed(seed, 3));
    simplifier.simplifyMax(ss->getSolutionPath());
  }
  out.path = solution_configs(*ss);
  return out;
}

}  // namespace canopy::motion
