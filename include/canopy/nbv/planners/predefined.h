#pragma once
// Dense predefined scanning ("predefined"): no planning; at every stop the stop's scripted
// views (ViewRequest::scripted: the mission's extra scan heights) once, in tour order, every
// one of them attempted (PlannerTraits: scripted, execute_whole_batch); the stop ends after
// that batch.

#include <memory>

#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::predefined {

/// The planner (registry name "predefined").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);

}  // namespace canopy::nbv::predefined
