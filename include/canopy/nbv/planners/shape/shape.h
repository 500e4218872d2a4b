#pragma once
// The shape-completion planner ("shape", docs/shape.md): the map-only analogue of the oracle's
// truth score. Each round, on the latest map:
//  - the fruit clusters of the stop's region (nbv/clusters: DBSCAN over confirmed fruit voxels)
//    are each fitted with a spheroid (mapping/shape_fit.h) whose surface, unseen part included,
//    is sampled every nbv.shape.spacing_m; a sample is already seen when a confirmed fruit voxel
//    centre lies within covered_m (the coverage rule's delta S);
//  - candidates lie on spheres (radii_m) around each fitted centre, looking at it (ours'
//    sampling and reach test);
//  - a view scores the unseen predicted points it would see: in the camera's image and depth
//    range, facing the camera (a fruit hides its own far side), each weighted by its sight
//    line's transmission (0 past an occupied voxel, unknown_transmit per unknown voxel), plus
//    uvc_weight x the view's unknown-voxel count (uvc, ours' rays);
//  - the best max_views views are tried in order until one succeeds; then it plans again. A view
//    that failed is not offered again at the stop; it is done when no view scores above 0.
// It reads only the map (no ground truth).

#include <memory>

#include "canopy/nbv/planners/shape/shape_params.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::shape {

/// The planner (registry name "shape").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// Its registry entry.
ViewPlannerEntry entry();

}  // namespace canopy::nbv::shape
