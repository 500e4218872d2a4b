#pragma once
// The metrics the field reports on a semantic map besides coverage and entropy
// (docs/background/evaluation.md, "Fruit detection and shape"), against the world's ground
// truth; only target (ripe) fruits are ground-truth fruits:
//  - detection: the map's fruit voxels (occupied, likeliest class = target) grouped into
//    clusters, 26-connected components of voxels (clusters smaller than min_voxels dropped);
//    clusters matched one-to-one to the fruits, closest pairs first, a pair matching when the
//    cluster centroid lies within match_size_fraction x the fruit's size (the largest side of
//    its bounding box) of the fruit's centre; precision = matched / clusters, recall =
//    matched / fruits, F1 their harmonic mean (0 when both are 0);
//  - per matched fruit: the centre error |centroid - centre|, and the relative volume errors
//    |V - V_true| / V_true of the voxel volume (voxels x resolution^3) and of an ellipsoid
//    fitted by moments to the voxel centres (semi-axes sqrt(3 lambda_i) of the covariance's
//    eigenvalues: exact for points spread evenly on a sphere, as a map holds a fruit's
//    surface), V_true the volume enclosed by the fruit's mesh;
//  - shape completion (docs/shape.md): each cluster also fitted with a spheroid by
//    mapping::fit_fruit_shape (the fruit-size prior of mapping.metrics.shape_fit), its centre
//    error and relative volume error beside the voxel-only figures (the centroid of the seen
//    surface lies in front of the fruit's centre; the voxel and moment volumes miss the unseen
//    side);
//  - voxel precision: a fruit voxel is true when a target fruit's surface sample lies within
//    half the voxel diagonal plus the samples' spacing of its centre, false elsewhere (what
//    segmentation noise costs: false fruit volume).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/types.h"
#include "canopy/mapping/shape_fit.h"
#include "canopy/world/ground_truth.h"

namespace canopy {
class PointKdTree;
}

namespace canopy::evaluation {

/// One cluster of mapped fruit voxels.
struct FruitCluster {
  Vec3 centroid = Vec3::Zero();     ///< Mean of the voxel centres.
  std::size_t voxels = 0;
  double voxel_volume_m3 = 0.0;     ///< voxels x resolution^3.
  double ellipsoid_volume_m3 = 0.0; ///< 4/3 pi a b c of the moment-fitted ellipsoid.
  Vec3 semi_axes = Vec3::Zero();    ///< a >= b >= c [m].
  mapping::FruitShape shape;        ///< The fitted spheroid (shape.ok false: too few voxels).
};

/// One cluster matched to one ground-truth fruit.
struct FruitMatch {
  int cluster = 0;                  ///< Index into FruitDetection::clusters.
  int instance_id = 0;              ///< The fruit's instance id.
  double centre_error_m = 0.0;
  double true_volume_m3 = 0.0;
  double voxel_volume_error = 0.0;      ///< |V_voxels - V_true| / V_true (NaN without V_true).
  double ellipsoid_volume_error = 0.0;  ///< |V_ellipsoid - V_true| / V_true (NaN without V_true).
  Vec3 true_centre = Vec3::Zero();
  double shape_centre_error_m = 0.0;    ///< |fitted centre - centre| (NaN without a fit).
  double shape_volume_error = 0.0;      ///< |V_fit - V_true| / V_true (NaN without a fit or V_true).
};

/// Fruit detection and shape over a whole map.
struct FruitDetection {
  std::size_t fruits = 0;           ///< Ground-truth (target) fruits.
  std::vector<FruitCluster> clusters;
  std::vector<FruitMatch> matches;
  double precision = 0.0, recall = 0.0, f1 = 0.0;
  /// Means over the matches (NaN without a match; volume errors over matches with V_true).
  double centre_error_m = 0.0, voxel_volume_error = 0.0, ellipsoid_volume_error = 0.0;
  /// Means over the matches with a shape fit (NaN without one).
  double shape_centre_error_m = 0.0, shape_volume_error = 0.0;
  std::size_t shape_fits = 0;       ///< Matches with a shape fit.

  nlohmann::json to_json() const;
};

/// Fruit voxels on a true fruit and elsewhere.
struct FruitVoxelPrecision {
  std::size_t true_voxels = 0, false_voxels = 0;
  double precision = 0.0;           ///< true / (true + false); 0 without fruit voxels.
  double false_volume_m3 = 0.0;     ///< false_voxels x resolution^3.
};

/// 26-connected components of voxels given by their centres on a grid of `resolution_m`
/// (members of a component touch by a face, an edge or a corner), components of fewer than
/// `min_voxels` dropped. Independent of the order of `centres`: members are summed in grid-cell
/// order and the clusters come in the order of their first cell, so an incremental evaluation
/// that keeps its voxels in another order gets the same numbers bit for bit.
std::vector<FruitCluster> fruit_clusters(const std::vector<Vec3>& centres, double resolution_m, int min_voxels,
                                         const mapping::ShapeFitParams& shape_fit = {});

/// Grid cell of a voxel centre packed into one integer, ordered by x, then y, then z: the order
/// in which fruit_clusters sums a cluster's voxels and orders the clusters.
std::int64_t fruit_cell(const Vec3& centre, double resolution_m);

/// The cluster of one component's voxel centres, given in fruit_cell order (not empty).
FruitCluster make_fruit_cluster(const std::vector<Vec3>& centres_in_cell_order, double resolution_m,
                                const mapping::ShapeFitParams& shape_fit = {});

/// The per-fruit table of matched fruits (fruit_shapes.csv of a run folder): instance_id,
/// voxels, true_x/y/z, true_volume_m3, then the voxel-only figures (centroid, its error, voxel
/// and moment-ellipsoid volumes and their errors) and the shape fit's (centre, its error,
/// semi-axes, volume, its error, RMS distance of the voxels to the fitted surface).
std::string fruit_shapes_csv(const FruitDetection& detection);

/// The moment-fitted ellipsoid of points: semi-axes sqrt(3 lambda_i) (descending) and volume.
void fit_ellipsoid(const std::vector<Vec3>& points, Vec3* semi_axes, double* volume_m3);

/// Matches clusters to the target fruits of `truth` (see the file comment).
FruitDetection detect_fruits(std::vector<FruitCluster> clusters, const world::GroundTruth& truth,
                             double match_size_fraction);

/// The target fruits' surface samples as a KD-tree: whether a fruit voxel lies on a true fruit
/// (its centre within half a voxel diagonal plus the sample spacing of a sample).
class TrueFruitSurface {
 public:
  TrueFruitSurface(const world::GroundTruth& truth, double resolution_m);
  /// The same test on a KD-tree of the target fruits' surface samples that the caller already
  /// holds (the incremental evaluator's; kept by reference, it must outlive this): no copy.
  TrueFruitSurface(const PointKdTree& target_points, double point_spacing_m, double resolution_m);
  ~TrueFruitSurface();
  TrueFruitSurface(const TrueFruitSurface&) = delete;
  TrueFruitSurface& operator=(const TrueFruitSurface&) = delete;
  bool on_fruit(const Vec3& voxel_centre) const;
  double resolution_m() const { return resolution_m_; }
  /// The farthest a sample can be from a voxel centre and still put it on a fruit: on_fruit()
  /// reads no sample farther than this.
  static double reach_m(double resolution_m, double point_spacing_m);

 private:
  std::unique_ptr<PointKdTree> owned_;  ///< Built by the first constructor.
  const PointKdTree* tree_ = nullptr;
  double resolution_m_ = 0.0;
  double reach2_ = 0.0;
};

/// Voxel precision from the counts of fruit voxels on and off the true fruits.
FruitVoxelPrecision fruit_voxel_precision(std::size_t true_voxels, std::size_t false_voxels, double resolution_m);

/// Voxel precision of fruit voxels (centres) against the target fruits' surface samples.
FruitVoxelPrecision fruit_voxel_precision(const std::vector<Vec3>& centres, const TrueFruitSurface& surface);

}  // namespace canopy::evaluation
