#pragma once
// The paper's cluster-centric planner ("ours"; Cuaran et al., Methods (ii)-(iii);
// docs/background/nbv_pipeline.md): fruit clusters of the map in the stop's region -> candidate
// views on a sphere around each centroid -> the reachability filter (the workspace filter's
// move and IK) -> the gain by name over the ray set by name -> the top-k views of every
// cluster not yet done (a cluster is done when its best gain is <= 0 and stays done while a
// later centroid lies within done_epsilon_m). A batch is executed in tour order
// (BatchOrder::kTour), then the map is clustered again. Its views' source is "nbv".
//
// The room: this file (registration and ours' selection of a round's clusters and candidates,
// which the oracle reuses), cluster_planner.h (the algorithm), ours_params.h (nbv.planner).

#include <memory>
#include <vector>

#include "canopy/nbv/clusters.h"
#include "canopy/nbv/planners/ours/cluster_planner.h"
#include "canopy/nbv/planners/ours/ours_params.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv::ours {

/// The planner (registry name "ours").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// Its registry entry.
ViewPlannerEntry entry();

/// ours' clusters of a round: the map's fruit clusters in the request's region (the index
/// refreshed first) that `done` does not hold. Sets batch->clusters, and batch->reason when
/// there is none; the time goes to the batch's "clustering" phase.
std::vector<Cluster> open_clusters(const ViewRequest& request, const ClusterParams& params, const DoneClusters& done,
                                   ViewBatch* batch);
/// ours' candidate filter: not a taken view, reachable (the reach test may move it), and still
/// not a taken view where it was moved to.
CandidateFilter candidate_filter(const ViewRequest& request, const TakenViews& taken);

}  // namespace canopy::nbv::ours
