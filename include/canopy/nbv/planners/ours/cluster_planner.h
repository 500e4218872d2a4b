#pragma once
// ours' algorithm, the cluster planner (paper Methods (iii)): every candidate of every fruit
// cluster is scored by casting its ray set through the voxel index and summing a gain; the
// top-k per cluster are returned, and a cluster whose best gain is <= 0 is done. No clusters
// -> an empty plan with its reason.
//
// Its selection of the candidates (ours_candidates: the sphere around each cluster, the
// filter) is a function of its own, so that the oracle scores exactly ours' candidates by the
// truth without a copy of it.

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/nbv/candidates.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/nbv/planners/ours/ours_params.h"
#include "canopy/nbv/view_evaluator.h"

namespace canopy::nbv {

/// What the planner found for one cluster.
struct ClusterResult {
  int cluster = -1;
  std::size_t candidates = 0;
  double best_gain = 0.0;
  bool done = false;              ///< Best gain <= 0 (or no candidate).
  std::vector<ScoredView> top;    ///< Up to top_k views with gain > 0, best first.
};

/// The planner's answer.
struct Plan {
  std::vector<ScoredView> views;        ///< All clusters' top views, best first (ties: cluster, candidate order).
  std::vector<ClusterResult> clusters;
  std::string reason;                   ///< Why `views` is empty ("no clusters", ...); empty otherwise.
  std::size_t candidates = 0;           ///< Candidates scored.
  std::size_t filtered = 0;             ///< Candidates the filter dropped.
  double ms_raycast = 0.0;              ///< Sum of the views' ray-casting times.
  double ms_candidates = 0.0;           ///< Sampling the candidates.
  double ms_filter = 0.0;               ///< Running the filter.
};

/// A candidate of a cluster that passed the filter, with its place among the cluster's sampled
/// candidates (which seeds its score).
struct KeptCandidate {
  std::size_t index = 0;
  Candidate candidate;
};

/// ours' candidates of cluster number `cluster`: the sphere of `params` around its centroid,
/// those `filter` keeps (it may move them; null keeps all), in sampling order. Adds the dropped
/// ones to *filtered and the time spent to *ms_sampling and *ms_filter when given.
std::vector<KeptCandidate> ours_candidates(const Cluster& cluster, int number, const CandidateParams& params,
                                           const CandidateFilter& filter, std::size_t* filtered,
                                           double* ms_sampling = nullptr, double* ms_filter = nullptr);

/// The cluster-centric next-best-view planner (ours).
class ClusterPlanner {
 public:
  ClusterPlanner(const NbvParams& params, const CameraIntrinsics& intrinsics);

  /// Samples candidates around each cluster, scores them with `gain` and `rays`, keeps the
  /// top-k per cluster. `seed` feeds the per-view seeds (rs). Deterministic.
  Plan plan(const VoxelIndex& index, const std::vector<Cluster>& clusters, const GainFunction& gain,
            const RaySetEntry& rays, std::uint64_t seed, const CandidateFilter& filter = nullptr,
            const CandidateObserver& observer = nullptr) const;

  /// The settings it plans with.
  const NbvParams& params() const { return params_; }

 private:
  NbvParams params_;
  CameraIntrinsics intrinsics_;
};

}  // namespace canopy::nbv
