#pragma once
// canopy's own planner ("reveal"), designed from what the oracle and the gain-vs-truth audit
// showed (docs/experiments/): the gains rank ours' candidates little better than chance against
// the truth, and ours plans a whole stop's batch on the map after the initial scan. reveal keeps
// ours' fruit clusters, candidate spheres (nbv.reveal.radii_m) and reach test, and
//  - scores a view by the fruit surface it would reveal: the map's "surface voxels" of every
//    cluster of the stop (unknown voxels next to a fruit voxel, and fruit voxels whose target
//    log-odds are not above nbv.cluster.min_logodds) in the camera's frustum and depth range
//    whose sight line from the camera crosses no occupied voxel and at most unknown_pass
//    unknown ones;
//  - plans one view at a time: the best views are tried in order until one succeeds, then the
//    map (with that view in it) is planned on again;
//  - is done at a stop when no candidate reveals a surface voxel; a view that failed is not
//    offered again at this stop.
// It reads only the map (no ground truth).

#include <memory>

#include "canopy/nbv/planners/reveal/reveal_params.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::reveal {

/// The planner (registry name "reveal").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// Its registry entry.
ViewPlannerEntry entry();

}  // namespace canopy::nbv::reveal
