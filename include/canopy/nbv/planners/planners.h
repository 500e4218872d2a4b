#pragma once
// The built-in view planners, one room each (nbv/planners/<name>/: algorithm, parameters,
// registration), listed in one table (MuJoCo MPC's GetTasks()). A new planner adds its room
// and one line to builtin_view_planners(): its entry carries its parameter section
// (ViewPlannerEntry::params), which becomes nbv.<name> of the settings; one from outside
// canopy calls register_view_planner instead.

#include <vector>

#include "canopy/nbv/view_planner.h"

namespace canopy::nbv {

/// The built-in planners' registry entries, in the registry's order: ours, frontier,
/// predefined, global, reveal, shape, then the oracles oracle and oracle_any.
std::vector<ViewPlannerEntry> builtin_view_planners();

}  // namespace canopy::nbv
