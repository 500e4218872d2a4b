#pragma once
// OMPL's side of ArmPlanner (internal to the motion module; OMPL stays in arm_search.cpp): the
// planner registry, the arm's joint space with its seeded sampler and its motion validator on
// several threads, and a search from a start to free goals within an iteration budget (the
// budget that decides; the wall clock is only a safety net), every random stream of it seeded
// from the request's seed.

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/timer.h"
#include "canopy/motion/arm_planner.h"

namespace canopy::motion {

/// What a search found (ArmPlanner::plan turns it into a PlanResult).
struct SearchOutcome {
  bool no_time = false;    ///< The time limit was used up before the search started.
  bool solved = false;     ///< An exact solution: `path` holds it.
  bool timed_out = false;  ///< The wall-clock safety net ended the search.
  int iterations = 0;      ///< Planner iterations run (PlanResult::iterations).
  std::string status;      ///< OMPL's word for the outcome ("Exact solution", "Timeout").
  std::vector<ArmConfig> path;  ///< With `solved`: start to goal, simplified when params.simplify.
};

/// Searches a path of the arm at `base` from `start` to one of `free_goals` with params.planner
/// within params.max_iterations iterations and what is left of params.time_limit_s since
/// `watch` started (read once the problem is set up). Every random stream is seeded from `seed`.
SearchOutcome search_path(const CollisionChecker& checker, const PlannerParams& params, const BasePose& base,
                          const ArmConfig& start, const std::vector<ArmConfig>& free_goals, std::uint64_t seed,
                          const Stopwatch& watch);

/// Turns OMPL's INFO messages (one per solve) off; warnings and errors still show.
void quiet_ompl_info();

}  // namespace canopy::motion
