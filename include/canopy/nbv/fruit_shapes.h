#pragma once
// The map's fruits completed by shape (docs/shape.md): the fruit clusters of nbv/clusters
// (DBSCAN over confirmed fruit voxels), each fitted with a spheroid (mapping/shape_fit.h), and
// the predicted surface points that no confirmed fruit voxel covers yet: what a view could still
// add to the fruits' surface coverage, as far as the map can tell. Map only, no ground truth.

#include <Eigen/Geometry>

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "canopy/mapping/semantic_octree.h"
#include "canopy/mapping/shape_fit.h"
#include "canopy/nbv/clusters.h"

namespace canopy::nbv {

/// One fruit cluster and its fitted shape.
struct FittedFruit {
  Cluster cluster;
  mapping::FruitShape shape;   ///< shape.ok false: too few voxels (centre = centroid, prior size).
  std::vector<Vec3> points;    ///< The cluster's voxel centres.
};

/// Fits kept between planning rounds: a cluster whose voxels did not change is not fitted
/// again (most clusters of a stop do not change from one view to the next).
class ShapeFitCache {
 public:
  /// The fit of `points` (its key: count and coordinates), fitted when new.
  const mapping::FruitShape& fit(const std::vector<Vec3>& points, const mapping::ShapeFitParams& params);
  std::size_t size() const { return fits_.size(); }

 private:
  std::unordered_map<std::uint64_t, mapping::FruitShape> fits_;
};

/// The map's fruits: clusters of the confirmed fruit voxels within `margin_m` of `region` (all
/// when null), fitted; those whose fitted centre lies in `region` are kept, largest first.
/// `confirmed`, when given, receives every confirmed fruit voxel centre considered.
std::vector<FittedFruit> fit_fruits(const mapping::SemanticOcTree& map, const ClusterParams& cluster,
                                    const mapping::ShapeFitParams& fit, const Eigen::AlignedBox3d* region = nullptr,
                                    double margin_m = 0.1, std::vector<Vec3>* confirmed = nullptr,
                                    ShapeFitCache* cache = nullptr);

/// The fruits' fitted centres, in their order (the targets planners sample candidates around).
std::vector<Vec3> fitted_centres(const std::vector<FittedFruit>& fruits);

/// A predicted surface point not yet covered.
struct PredictedPoint {
  Vec3 position = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  ///< Outward unit normal of the fitted surface.
  int fruit = 0;                ///< Index into the fruits.
};

/// The fruits' predicted surface points (every `spacing_m`) with no point of `confirmed` within
/// `covered_m`.
std::vector<PredictedPoint> unseen_surface(const std::vector<FittedFruit>& fruits, const std::vector<Vec3>& confirmed,
                                           double spacing_m, double covered_m);

}  // namespace canopy::nbv
