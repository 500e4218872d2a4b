#pragma once
// Job: time one view's information gain on a realistic map (a world mapped from a set of
// views) for each ray set, with the fast traversal (flat voxel index) and the slow reference
// (computeRayKeys + a tree search per key) in the same run. `canopy bench gain` prints it.

#include <string>
#include <utility>
#include <vector>

#include "canopy/mapping/semantic_octree.h"
#include "canopy/settings/settings.h"

namespace canopy::jobs {

/// What bench_gain measures.
struct BenchGainParams {
  std::string world_file = "worlds/default.yaml";
  std::string views = "ring";      ///< Views that build the map: 'ring', 'aisle' or a pose file.
  std::string gain = "osamcep";    ///< Gain timed for every ray set.
  int candidates = 200;            ///< Candidate views timed, spread over all clusters.
  double min_ms = 400.0;           ///< Minimum time per measurement [ms].
};

/// One ray set's timings: (a) gain per view, (b) traversal with voxel values, (c) traversal only.
struct BenchGainRow {
  std::string rays;
  double rays_per_view = 0.0;
  double voxels_per_view = 0.0;
  double gain_ms_fast = 0.0, gain_ms_reference = 0.0;        ///< (a) ms per view.
  double values_ns_fast = 0.0, values_ns_reference = 0.0;    ///< (b) ns per voxel.
  double traverse_ns_fast = 0.0, traverse_ns_reference = 0.0;  ///< (c) ns per voxel.
  double gain_sum_fast = 0.0, gain_sum_reference = 0.0;      ///< Sums of the gains of one pass (they must agree).
};

/// What bench_gain found: the map, its index, and the timings.
struct BenchGainResult {
  std::string world_name;
  std::size_t views = 0;
  mapping::VoxelCounts counts;
  std::size_t index_bricks = 0, index_states = 0;
  double index_mb = 0.0, index_build_ms = 0.0;
  std::size_t clusters = 0, candidates = 0;
  std::vector<BenchGainRow> rows;                          ///< One per ray set (nbv::ray_set_names()).
  std::vector<std::pair<std::string, double>> gain_ms;     ///< Every gain with our ray set: ms per view.
};

/// Builds the map of `params.world_file` from its views with `bundle`'s mapping settings and
/// times the gain of candidate views of its clusters. InputError for a map without clusters.
BenchGainResult bench_gain(const BenchGainParams& params, const settings::Settings& bundle);

}  // namespace canopy::jobs
