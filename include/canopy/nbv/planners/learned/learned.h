#pragma once
// The planner on the learned view scorer ("learned", docs/learned.md). Each round, on the latest
// map: the fruits of the stop region fitted as the shape planner fits them, from the voxels hit as
// fruit once or more (fruit_min_logodds, where the shape planner needs two); candidates on
// spheres (radii_m) around each fitted centre, through ours' reach test; each candidate's view
// features (nbv/view_features.h) scored by the model (nbv/view_ranker.h), trained against the
// truth on tuning worlds only; candidates that would see neither unseen predicted fruit surface
// nor unknown space are left out. The best max_views views are tried in order until one
// succeeds, then it plans again. A view that failed is not offered again at the stop. It reads
// only the map (no ground truth); a bad model file is refused when the planner is made.

#include <memory>

#include "canopy/nbv/planners/learned/learned_params.h"
#include "canopy/nbv/view_features.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::learned {

/// The planner (registry name "learned"); throws InputError naming the model file when it cannot be used.
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// How learned computes its features and finds its fruits (the oracle on learned's candidates
/// finds the same fruits).
ViewFeatureParams feature_params(const LearnedParams& params);
/// Its registry entry.
ViewPlannerEntry entry();

}  // namespace canopy::nbv::learned
