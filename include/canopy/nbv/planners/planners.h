#pragma once
// The built-in view planners, one room each (nbv/planners/<name>/: algorithm, parameters,
// registration), listed in one table (MuJoCo MPC's GetTasks()). A new planner adds its room
// and one line to builtin_view_planners(); one from outside canopy calls
// register_view_planner instead.

#include <vector>

#include "canopy/nbv/view_planner.h"

namespace canopy::nbv {

/// The built-in planners' registry entries, in the registry's order: ours, frontier,
/// predefined, global, reveal, shape.
std::vector<ViewPlannerEntry> builtin_view_planners();

}  // namespace canopy::nbv
