// ours' cluster planner (planners/ours/cluster_planner.h).

#include "canopy/nbv/planners/ours/cluster_planner.h"

#include <algorithm>

#include "canopy/common/random.h"
#include "canopy/common/timer.h"

namespace canopy::nbv {

std::vector<KeptCandidate> ours_candidates(const Cluster& cluster, int number, const CandidateParams& params,
                                           const CandidateFilter& filter, std::size_t* filtered, double* ms_sampling,
                                           double* ms_filter) {
  const Stopwatch sampling;
  std::vector<Candidate> cands = sample_candidates(cluster.centroid, number, params);
  if (ms_sampling) *ms_sampling += sampling.ms();
  std::vector<KeptCandidate> kept;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (filter) {
      const Stopwatch filtering;
      const bool keep = filter(&cands[i]);
      if (ms_filter) *ms_filter += filtering.ms();
      if (!keep) {
        ++*filtered;
        continue;
      }
    }
    kept.push_back({i, cands[i]});
  }
  return kept;
}

ClusterPlanner::ClusterPlanner(const NbvParams& params, const CameraIntrinsics& intrinsics)
    : params_(params), intrinsics_(intrinsics) {}

Plan ClusterPlanner::plan(const VoxelIndex& index, const std::vector<Cluster>& clusters, const GainFunction& gain,
                          const RaySetEntry& rays, std::uint64_t seed, const CandidateFilter& filter,
                          const CandidateObserver& observer) const {
  Plan plan;
  if (clusters.empty()) {
    plan.reason = "no clusters";
    return plan;
  }
  ViewEvaluator eval(index, intrinsics_, params_.rays);
  const int top_k = params_.planner<OursParams>().top_k;
  std::size_t filtered = 0;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    ClusterResult cr;
    cr.cluster = int(c);
    const std::vector<KeptCandidate> kept =
        ours_candidates(clusters[c], int(c), params_.candidates, filter, &filtered, &plan.ms_candidates, &plan.ms_filter);
    std::vector<ScoredView> scored;
    for (const KeptCandidate& k : kept) {
      const std::uint64_t view_seed = mix_seed(seed, c * 100000 + k.index);
      const Candidate& cand = k.candidate;
      ScoredView sv{cand, eval.evaluate(cand.T_world_camera, cand.target, gain, rays, view_seed)};
      plan.ms_raycast += sv.score.ms;
      if (observer) observer(sv);
      scored.push_back(sv);
    }
    cr.candidates = scored.size();
    plan.candidates += scored.size();
    std::stable_sort(scored.begin(), scored.end(),
                     [](const ScoredView& a, const ScoredView& b) { return a.score.gain > b.score.gain; });
    cr.best_gain = scored.empty() ? 0.0 : scored.front().score.gain;
    cr.done = !(cr.best_gain > 0.0);
    if (!cr.done)
      for (const ScoredView& sv : scored) {
        if (int(cr.top.size()) >= top_k || !(sv.score.gain > 0.0)) break;
        cr.top.push_back(sv);
      }
    plan.views.insert(plan.views.end(), cr.top.begin(), cr.top.end());
    plan.clusters.push_back(std::move(cr));
  }
  std::stable_sort(plan.views.begin(), plan.views.end(),
                   [](const ScoredView& a, const ScoredView& b) { return a.score.gain > b.score.gain; });
  plan.filtered = filtered;
  if (plan.views.empty()) {
    if (plan.candidates == 0)
      plan.reason = filtered > 0 ? "every candidate was filtered out" : "no candidates";
    else
      plan.reason = "every cluster is done (best gain <= 0)";
  }
  return plan;
}

}  // namespace canopy::nbv
