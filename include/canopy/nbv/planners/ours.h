#pragma once
// The paper's cluster-centric planner ("ours"; Cuaran et al., Methods (ii)-(iii);
// docs/background/nbv_pipeline.md): fruit clusters of the map in the stop's region -> candidate
// views on a sphere around each centroid -> the reachability filter (the workspace filter's
// move and IK) -> the gain by name over the ray set by name -> the top-k views of every
// cluster not yet done (a cluster is done when its best gain is <= 0 and stays done while a
// later centroid lies within done_epsilon_m). A batch is executed in tour order
// (BatchOrder::kTour), then the map is clustered again.

#include <memory>

#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::ours {

/// The planner (registry name "ours").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);

}  // namespace canopy::nbv::ours
