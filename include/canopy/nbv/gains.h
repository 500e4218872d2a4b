#pragma once
// Information-gain functions of a candidate view, chosen by name from one registry
// (gain_registry). A view's gain is the sum of its rays' gains; each ray gain reads the
// voxels the ray visits, in order from the camera (RayVoxel, from VoxelIndex::cast).
//
// Definitions (paper Eq. 1-4, docs/background/nbv_pipeline.md), with these interpretations:
//  - osamcep: sum of P_v(x) H(x) over voxels that are unknown (never observed) or target
//    voxels (occupied, most likely class = target), close to the target centroid.
//    P_v(x_n) = prod_{i<n} (1 - p_occ(x_i)), unknown p_occ = 0.5; H is the voxel's multi-class
//    entropy over the map's categories (SSMI's unseen prior for unknown voxels). "Close"
//    (GainParams::proximity): per_voxel, the paper's equation, tests each voxel's centre
//    distance < max_dist; per_segment_end, the released code, walks the ray as run-length
//    segments of identical voxels (equal palette ids) and tests every voxel of a segment with
//    the distance of the segment's last voxel, so an all-unknown ray ending near the target
//    counts from the camera on (about 2 H), where per_voxel counts only its last few voxels at
//    P_v 0.5^15..0.5^25.
//  - ae: sum of H_b(p_occ) along the ray over the voxels before the first one with
//    p_occ >= ae_stop_occupancy (the prototype sums; Delmerico divides by hitting rays).
//  - uvc: count of unknown voxels (no leaf, or unknown_low < p_occ <= unknown_high) before the
//    first voxel with p_occ > unknown_high, which blocks the ray (Zaenker's rule). Known free
//    voxels are passed through; the prototype stopped at the first known voxel of any kind,
//    which makes the count vanish once the camera sits in observed free space.
//  - uvpc: uvc restricted to voxels with d < max_dist, each weighted base + (max_dist - d) / max_dist.
//  - oae: sum of H_b(p_occ) P_v over the whole ray (visibility as prod (1 - p_occ)).
//  - mi: SSMI's Shannon mutual information between the map and the ray's measurement (range
//    cell n and class k, or no hit), in closed form over run-length segments of identical
//    voxels; each segment's categorical distribution is normalised over its categories. Plain
//    SSMI: the prototype's extra log-odds offsets for fruit / non-fruit voxels are not applied;
//    an unknown voxel is a fresh leaf (p_occ 0.5, classes equally likely).
//  - rs: random score in (0, 1], seeded per view; casts no rays.
// With unknown voxels at p_occ = 0.5, P_v halves per unknown 1.5 cm voxel, so the visibility
// gains (osamcep, oae) favour views whose rays run through already observed free space; a
// gain is positive whenever any counted voxel lies on a ray, so "done" (<= 0) means nothing
// unknown or uncertain-target is left near the cluster, not "little is left".

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "canopy/nbv/nbv_params.h"
#include "canopy/nbv/voxel_index.h"

namespace canopy::nbv {

/// A view-scoring function (OMPL-style small const interface).
class GainFunction {
 public:
  virtual ~GainFunction() = default;
  /// Registry name ("osamcep", ...).
  virtual std::string name() const = 0;
  /// Gain of one ray's voxels, in order from the camera; 0 for an empty ray.
  virtual double ray_gain(const RayVoxel* voxels, std::size_t count) const = 0;
  /// False when the gain ignores the map (rs): the evaluator casts no rays.
  virtual bool uses_rays() const { return true; }
  /// The view's gain from the sum of its ray gains; `view_seed` identifies the view (rs).
  virtual double view_gain(double ray_sum, std::uint64_t /*view_seed*/) const { return ray_sum; }
};

/// One registry entry.
struct GainEntry {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<GainFunction>(const GainParams&)> make;
  /// It reads GainParams::proximity (osamcep): an audit scores each proximity test apart.
  bool uses_proximity = false;
};

/// All gains, in the paper's order: osamcep, ae, uvc, uvpc, oae, mi, rs.
const std::vector<GainEntry>& gain_registry();
/// Names of the registry, in order.
std::vector<std::string> gain_names();
/// The gain called `name`; throws InputError naming `where` and the valid names otherwise.
std::unique_ptr<GainFunction> make_gain(const std::string& name, const GainParams& params,
                                        const std::string& where = "gain");

/// SSMI mutual information of a ray computed cell by cell (no run-length closed form): the
/// slow reference for the "mi" gain, for tests.
double mutual_information_per_cell(const RayVoxel* voxels, std::size_t count);

}  // namespace canopy::nbv
