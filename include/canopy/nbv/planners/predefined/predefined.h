#pragma once
// Dense predefined scanning ("predefined"): no planning; at every stop the stop's scripted
// views (ViewRequest::scripted: the mission's extra scan heights) once, in tour order, every
// one of them attempted (PlannerTraits: scripted, execute_whole_batch); the stop ends after
// that batch. A scripted view that fails, of the initial scan or its own, is replaced
// (PlannerTraits::replaces_failed, replace_failed): the nearest reachable view of the same
// scan pattern that no scripted view or earlier replacement of the stop took, as the paper's
// predefined scan executed all its views (docs/mission.md).

#include <memory>

#include "canopy/nbv/planners/predefined/predefined_params.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::predefined {

/// The planner (registry name "predefined").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// Its registry entry.
ViewPlannerEntry entry();

}  // namespace canopy::nbv::predefined
