// canopy's own planner (planners/reveal.h).

#include "canopy/nbv/planners/reveal.h"

#include <algorithm>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/nbv/clusters.h"

namespace canopy::nbv::reveal {

namespace {

class RevealPlanner : public ViewPlanner {
 public:
  explicit RevealPlanner(const ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), settings_(s), params_(s.params.reveal),
        gain_(make_gain(s.params.reveal.gain, s.params.gain, "nbv.reveal.gain")), rays_(ray_set(s.method.rays, "rays")),
        done_(s.params.views), failed_(s.params.views) {}

  std::string name() const override { return "reveal"; }

  void taken(const Pose& T) override {
    ViewPlanner::taken(T);
    // The views of the batch before the one taken failed.
    ViewRules loose;
    loose.taken_position_m = 0.03;
    loose.taken_angle_deg = 10.0;
    TakenViews reached(loose);
    reached.add(T);
    for (const Pose& p : pending_) {
      if (reached.contains(p)) break;
      failed_.add(p);
    }
    pending_.clear();
  }

  void begin_stop() override {
    failed_ = TakenViews(settings_.params.views);
    pending_.clear();
  }

  ViewBatch next(const ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    for (const Pose& p : pending_) failed_.add(p);  // nothing of the last batch succeeded
    pending_.clear();
    ViewBatch batch;
    batch.order = BatchOrder::kUtility;
    std::vector<Cluster> clusters;
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      for (Cluster& c : find_clusters(*req.map, settings_.params.cluster, &req.region))
        if (!done_.contains(c.centroid)) clusters.push_back(c);
    }
    batch.clusters = clusters.size();
    if (clusters.empty()) {
      batch.finished = true;
      batch.reason = done_.size() ? "every cluster in reach is done" : "no fruit clusters in reach";
      return batch;
    }
    std::vector<ScoredView> scored;
    std::vector<double> best(clusters.size(), 0.0);
    std::vector<bool> any(clusters.size(), false);
    ViewEvaluator eval(*req.index, settings_.intrinsics, settings_.params.rays);
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      std::size_t i = 0;
      for (const double r : params_.radii_m) {
        CandidateParams cp = settings_.params.candidates;
        cp.sphere.radius_m = r;
        std::vector<Candidate> cands;
        {
          ScopedPhase phase(batch.times, "candidates");
          cands = sample_candidates(clusters[c].centroid, int(c), cp);
        }
        for (Candidate& cand : cands) {
          ++i;
          {
            ScopedPhase phase(batch.times, "filtering");
            if (taken_.contains(cand.T_world_camera) || failed_.contains(cand.T_world_camera) ||
                (req.reach && !req.reach(&cand)) || taken_.contains(cand.T_world_camera) ||
                failed_.contains(cand.T_world_camera)) {
              ++batch.filtered;
              continue;
            }
          }
          ScopedPhase phase(batch.times, "scoring");
          ScoredView sv{cand, eval.evaluate(cand.T_world_camera, cand.target, *gain_, rays_, mix_seed(req.seed, c * 100000 + i))};
          if (req.on_scored) req.on_scored(sv);
          best[c] = std::max(best[c], sv.score.gain);
          any[c] = true;
          scored.push_back(sv);
        }
      }
    }
    batch.candidates = scored.size();
    // The relative done rule: the first best gain of a cluster is its reference.
    std::vector<bool> done(clusters.size(), false);
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      const double ref = reference(clusters[c].centroid, best[c]);
      done[c] = !any[c] || !(best[c] > 0.0) || best[c] <= params_.done_fraction * ref;
      if (done[c]) done_.mark(clusters[c].centroid);
    }
    std::stable_sort(scored.begin(), scored.end(),
                     [](const ScoredView& a, const ScoredView& b) { return a.score.gain > b.score.gain; });
    for (const ScoredView& sv : scored) {
      if (int(batch.views.size()) >= params_.max_views) break;
      if (done[std::size_t(sv.candidate.cluster)] || !(sv.score.gain > 0.0)) continue;
      batch.views.push_back(planned_view(sv.candidate, sv.score.gain, "nbv"));
      pending_.push_back(sv.candidate.T_world_camera);
    }
    batch.finished = batch.views.empty();
    if (batch.finished) batch.reason = scored.empty() ? "every candidate was filtered out" : "every cluster is done";
    return batch;
  }

 private:
  // The best gain a cluster had when first planned (matched by centroid as done clusters are).
  double reference(const Vec3& centroid, double best_now) {
    for (const auto& [c, ref] : references_)
      if ((c - centroid).norm() <= settings_.params.views.done_epsilon_m) return ref;
    references_.push_back({centroid, best_now});
    return best_now;
  }

  ViewPlannerSettings settings_;
  RevealParams params_;
  std::unique_ptr<GainFunction> gain_;
  const RaySetEntry& rays_;
  DoneClusters done_;
  TakenViews failed_;
  std::vector<Pose> pending_;
  std::vector<std::pair<Vec3, double>> references_;
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new RevealPlanner(settings));
}

}  // namespace canopy::nbv::reveal
