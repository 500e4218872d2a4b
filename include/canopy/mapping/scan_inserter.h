#pragma once
// Inserting one labelled scan into the semantic octree (docs/background/semantic_map.md, issue point 3):
// the cloud is voxel-filtered at the map resolution (one hit per voxel, the majority label);
// endpoints within max_range_m are hits; the cells along each ray from the sensor to the
// endpoint voxel's centre, up to ray_range_m, are updated as free, except cells hit in the
// same scan; every voxel gets at most one update per scan, applied in one Morton-ordered
// pass over the tree.
//
// The free cells of a scan are collected in a dense bit grid over the rays' bounding box
// (no hashing), sorted by radix sort, and merged with the hits. Results do not depend on the
// number of threads.

#include <cstdint>
#include <vector>

#include "canopy/mapping/semantic_octree.h"
#include "canopy/perception/labelled_cloud.h"

namespace canopy::mapping {

/// What one insertion did.
struct InsertStats {
  std::size_t points = 0;          ///< Points in the cloud.
  std::size_t bad_point = 0;       ///< NaN or inf coordinates (skipped).
  std::size_t bad_label = 0;       ///< Label outside the class list (skipped).
  std::size_t outside_map = 0;     ///< Outside the octree's addressable range (skipped).
  std::size_t beyond_range = 0;    ///< Farther than max_range_m: ray only, no hit.
  std::size_t hit_voxels = 0;      ///< Distinct voxels updated as hits.
  std::size_t hit_updates = 0;     ///< Hit updates (= hit_voxels, or more with per_endpoint insertion).
  std::size_t free_voxels = 0;     ///< Distinct voxels updated as free.
  std::size_t rays = 0;            ///< Rays cast (one per distinct endpoint voxel).
  UpdateCounts tree;               ///< Applied, saturated, created, pruned.
  double ms_filter = 0.0;          ///< Keys, voxel filter and votes.
  double ms_raycast = 0.0;         ///< Free-space ray casting and collection.
  double ms_update = 0.0;          ///< Tree update.
  double ms_total = 0.0;

  /// Points skipped as bad input (bad_point + bad_label + outside_map).
  std::size_t skipped() const { return bad_point + bad_label + outside_map; }
};

/// Free cells of one ray, as OctoMap's computeRayKeys: every voxel the segment from
/// `origin` to `end` passes through, except the voxel containing `end`. Appends to `keys`;
/// false when either point is outside the tree. The slow reference for the inserter.
bool ray_free_keys(const SemanticOcTree& map, const Vec3& origin, const Vec3& end,
                   std::vector<octomap::OcTreeKey>* keys);

/// One ray's free-space segment (float, as OctoMap's ray casting).
struct RaySegment {
  octomap::point3d origin, end;
};

/// Inserts scans into one map, reusing its scratch buffers between scans.
class ScanInserter {
 public:
  explicit ScanInserter(SemanticOcTree& map);

  /// Inserts one labelled cloud (points and origin in the map's world frame).
  InsertStats insert(const perception::LabelledCloud& cloud);

  /// The hit and free updates insert() would apply, sorted by code (for tests and the
  /// benchmark). Fills `stats` up to the ray casting. With per_endpoint insertion these are
  /// every voxel's first update; a voxel's further hits of the scan are in extra_hits().
  void compute_updates(const perception::LabelledCloud& cloud, std::vector<VoxelUpdate>* updates,
                       InsertStats* stats);
  /// per_endpoint insertion: the further hits of the last compute_updates(), in layers (layer
  /// m holds the (m+2)-th hit of every voxel hit more than m+1 times, sorted by code), which
  /// insert() applies after the first batch, one layer after another.
  const std::vector<std::vector<VoxelUpdate>>& extra_hits() const { return extra_; }

  /// The voxel updates the last insert() applied (hits and pass-throughs, sorted by code):
  /// what caches beside the map (a collision environment) must look at again.
  const std::vector<VoxelUpdate>& last_updates() const { return updates_; }
  /// Per entry of last_updates(): SemanticOcTree::kOccupiedBefore / kOccupiedAfter (the
  /// voxel's occupancy before the scan and after all of its updates).
  const std::vector<std::uint8_t>& last_occupancy() const { return occupancy_; }
  /// Free-space rays four at a time in AVX2 lanes where the processor has them (default); off:
  /// one at a time. The same voxels either way (for tests and the benchmark).
  void set_vectorised(bool on) { vectorised_ = on; }

 private:
  SemanticOcTree& map_;
  std::vector<std::uint64_t> values_, scratch_;  // per-point (code << 8 | label), sort buffer
  std::vector<std::uint64_t> free_codes_;
  std::vector<VoxelUpdate> hits_, updates_;
  std::vector<std::uint8_t> occupancy_, layer_occupancy_;  // per update: occupied before / after
  bool vectorised_ = true;
  std::vector<std::vector<VoxelUpdate>> extra_;  // per_endpoint: further hits, in layers
  perception::LabelledCloud filtered_;           // per_endpoint: the camera-frame voxel filter's points
  std::vector<std::uint64_t> ray_targets_;       // endpoint voxel codes, bit 63: beyond range
  std::vector<std::uint64_t> crossed_, hit_cells_;  // bits over the rays' box: crossed (a grid per thread), hit
  std::vector<RaySegment> segments_;
  std::vector<std::vector<std::uint64_t>> slices_;  // free codes per range of the box's cells
};

}  // namespace canopy::mapping
