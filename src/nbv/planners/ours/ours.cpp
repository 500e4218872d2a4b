// The paper's cluster-centric planner (planners/ours/ours.h).

#include "canopy/nbv/planners/ours/ours.h"

#include <algorithm>

#include "canopy/common/error.h"

namespace canopy::nbv::ours {

std::vector<Cluster> open_clusters(const ViewRequest& req, const ClusterParams& params, const DoneClusters& done,
                                   ViewBatch* batch) {
  std::vector<Cluster> clusters;
  {
    ScopedPhase phase(batch->times, "clustering");
    req.index->refresh(*req.map);
    for (Cluster& c : find_clusters(*req.map, params, &req.region))
      if (!done.contains(c.centroid)) clusters.push_back(c);
  }
  batch->clusters = clusters.size();
  if (clusters.empty()) batch->reason = done.size() ? "every cluster in reach is done" : "no fruit clusters in reach";
  return clusters;
}

CandidateFilter candidate_filter(const ViewRequest& req, const TakenViews& taken) {
  // Taken views are dropped before and after the reachability move.
  return [&req, &taken](Candidate* c) {
    if (taken.contains(c->T_world_camera)) return false;
    if (req.reach && !req.reach(c)) return false;
    return !taken.contains(c->T_world_camera);
  };
}

namespace {

// The paper's cluster-centric planner.
class OursPlanner : public ViewPlanner {
 public:
  explicit OursPlanner(const ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), settings_(s), planner_(s.params, s.intrinsics),
        gain_(make_gain(s.method.gain, s.params.gain, "gain")), rays_(ray_set(s.method.rays, "rays")),
        done_(s.params.views) {}

  std::string name() const override { return "ours"; }

  ViewBatch next(const ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    ViewBatch batch;
    batch.order = BatchOrder::kTour;
    const std::vector<Cluster> clusters = open_clusters(req, settings_.params.cluster, done_, &batch);
    if (clusters.empty()) {
      batch.finished = true;
      return batch;
    }
    const Stopwatch watch;
    const Plan plan =
        planner_.plan(*req.index, clusters, *gain_, rays_, req.seed, candidate_filter(req, taken_), req.on_scored);
    const double total_s = watch.seconds();
    batch.times.add("candidates", plan.ms_candidates * 1e-3);
    batch.times.add("filtering", plan.ms_filter * 1e-3);
    batch.times.add("scoring", std::max(0.0, total_s - (plan.ms_candidates + plan.ms_filter) * 1e-3));
    batch.candidates = plan.candidates;
    batch.filtered = plan.filtered;
    for (const ClusterResult& cr : plan.clusters)
      if (cr.done) done_.mark(clusters[static_cast<std::size_t>(cr.cluster)].centroid);
    // "nbv", not "ours": the tag views.csv has always had for ours' views.
    for (const ScoredView& sv : plan.views) batch.views.push_back(planned_view(sv.candidate, sv.score.gain, "nbv"));
    batch.reason = plan.reason;
    batch.finished = batch.views.empty();
    return batch;
  }

 private:
  ViewPlannerSettings settings_;
  ClusterPlanner planner_;
  std::unique_ptr<GainFunction> gain_;
  const RaySetEntry& rays_;
  DoneClusters done_;
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new OursPlanner(settings));
}

ViewPlannerEntry entry() {
  return {"ours", "cluster-centric NBV: fruit clusters, candidates on a sphere, workspace filter, gain, top-k, tour",
          make_planner, false,
          planner_section<OursParams>("The paper's cluster planner (method ours)", "planner")};
}

}  // namespace canopy::nbv::ours
