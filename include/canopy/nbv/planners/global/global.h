#pragma once
// A global view planner ("global"), after Zaenker et al.'s view-motion planning (GO-VMP:
// set cover of target voxels plus a shortest path; docs/background/global_planner.md): at each
// request, every candidate of every fruit cluster in the stop's region (the same candidates
// and reachability filter as ours) is ray cast with the method's ray set through the voxel
// index, as the gains are; a view observes a voxel while the visibility prod (1 - p_occ) of the
// occupied voxels before it on a ray is at least min_visibility (unknown voxels do not occlude,
// as in the frontier planner's utility ray), and the voxels that count are unknown
// or target voxels within roi_radius_m of a cluster centroid, each weighing its entropy. The
// batch is a weighted set cover chosen greedily (Chvatal): repeatedly the view with the most
// newly observed weight per cost, cost = 1 + motion_weight_per_rad x its joint-space distance
// from the arm now, until the batch observes cover_fraction of what all candidates observe or
// holds the stop's remaining budget of views. Greedy weighted set cover costs at most H(d) <=
// 1 + ln d times the cheapest cover (d = most voxels one view observes); limited to k views,
// unit costs, it observes at least 1 - 1/e of the best k views' weight (Nemhauser, Wolsey and
// Fisher 1978). The controller executes the batch in the order of its shortest open tour
// (BatchOrder::kTour) and asks again, so the cover is re-planned after each batch.

#include <cstdint>
#include <memory>
#include <vector>

#include "canopy/nbv/planners/global/global_params.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::global {

/// One candidate with the voxels it observes (ids into a weight table) and its cost.
struct CoverSet {
  std::vector<std::uint32_t> items;
  double cost = 1.0;
};

/// Greedy weighted set cover: indices of the chosen sets, in the order chosen. Stops when no
/// set adds weight, when `max_sets` are chosen, or once the chosen sets hold `fraction` of the
/// weight all sets hold. *covered (when given) receives the weight the chosen sets hold and
/// *total that of all sets. Ties go to the lower index.
std::vector<int> greedy_cover(const std::vector<CoverSet>& sets, const std::vector<double>& weights, int max_sets,
                              double fraction, double* covered = nullptr, double* total = nullptr,
                              std::vector<double>* gains = nullptr);

/// The planner (registry name "global").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// Its registry entry.
ViewPlannerEntry entry();

}  // namespace canopy::nbv::global
