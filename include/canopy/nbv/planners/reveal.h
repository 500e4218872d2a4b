#pragma once
// canopy's own planner ("reveal"), designed from what the oracle and the gain-vs-truth audit
// showed (docs/experiments/): ours' fruit clusters, candidate spheres (nbv.reveal.radii_m) and
// reach test, but
//  - one view at a time: the best views of the round are tried in order until one succeeds,
//    then the map (with that view in it) is planned on again, so no view is chosen on a map
//    that misses the views of its own batch;
//  - the gain nbv.reveal.gain (the one that ranked views closest to the truth);
//  - a relative "done" rule: a cluster is done when its best gain has fallen to done_fraction
//    of the best gain it had when first planned (ours waits for exactly 0, which the
//    probabilistic gains never reach);
//  - a view that failed is not offered again at this stop.
// It reads only the map (no ground truth).

#include <memory>

#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::reveal {

/// The planner (registry name "reveal").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);

}  // namespace canopy::nbv::reveal
