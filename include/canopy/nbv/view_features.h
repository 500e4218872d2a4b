#pragma once
// The features of a candidate view that a learned view scorer reads (issue 47): every gain of
// the registry over the cheap ray sets, the shape fit's predicted unseen surface in view and how
// much of it is blocked, the fit's quality, how consistently the target fruit's voxels were
// labelled fruit, how much of it is seen already, the view's geometry (distance and angle to
// the target, the move from the camera now), and the target fruit's evidence (its voxels' class
// log-odds, what lies inside and around its fit). Map only, no ground truth: the candidate audit
// records them beside the truth (training data), a planner computes the same at planning.
// One feature set, one order (view_feature_names()); a model names the ones it reads
// (nbv/view_ranker.h reads them by name).

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/mapping/shape_fit.h"
#include "canopy/nbv/candidates.h"
#include "canopy/nbv/fruit_shapes.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/nbv/ray_sets.h"
#include "canopy/nbv/view_evaluator.h"
#include "canopy/nbv/voxel_index.h"

namespace canopy::nbv {

/// How the shape features are computed (the shape planner's defaults, docs/shape.md).
struct ViewFeatureParams {
  mapping::ShapeFitParams fit;
  double spacing_m = 0.01;         ///< Predicted surface points every this much [m].
  double covered_m = 0.015;        ///< A predicted point is seen with a confirmed fruit voxel this close [m].
  double unknown_transmit = 0.97;  ///< Sight-line transmission per unknown voxel.
  double margin_m = 0.1;           ///< Fruit voxels within this of the stop region are clustered [m].
  /// A voxel is one of a fruit's (clustered, fitted, confirmed) when its most likely class is the
  /// target with log-odds above this (the other fields of the clustering: NbvParams::cluster).
  double fruit_min_logodds = ClusterParams{}.min_logodds;
  /// `base` (NbvParams::cluster) with this threshold: the clustering of the features' fruits.
  ClusterParams clustering(ClusterParams base) const {
    base.min_logodds = fruit_min_logodds;
    return base;
  }
};

/// True when no point within `radius_m` of `centre_world` can lie in the view of a camera at
/// T_world_camera: every such point is nearer than the minimum range, beyond the maximum range
/// (depth along the optical axis) or projects outside the image, with a margin far above
/// rounding. The predicted-surface loop of ViewFeatures::compute skips the points of a fruit
/// whose bounding sphere this says is out of view (it would skip each of them anyway).
bool sphere_out_of_view(const CameraIntrinsics& intrinsics, const Pose& T_world_camera, const Vec3& centre_world,
                        double radius_m);

/// The feature names, in the order compute() writes them.
const std::vector<std::string>& view_feature_names();

/// Computes the features of candidates, one planning round at a time.
class ViewFeatures {
 public:
  ViewFeatures(const CameraIntrinsics& intrinsics, const NbvParams& nbv, const ViewFeatureParams& params);
  ~ViewFeatures();

  /// A new round on `map` (whose `index` is refreshed) for the stop `region`, the camera now at
  /// T_world_camera: the fruits fitted (kept between rounds while their voxels do not change)
  /// and their unseen predicted surface.
  void begin_round(const mapping::SemanticOcTree& map, const VoxelIndex& index, const Eigen::AlignedBox3d& region,
                   const Pose& T_world_camera);
  /// The fruits of the round.
  const std::vector<FittedFruit>& fruits() const { return fruits_; }
  /// The features of a view at T_world_camera looking at `target` (view_feature_names() order).
  /// The ray sets' features of a view asked before (the same pose and target, bit for bit) are
  /// kept while no voxel they read changed (VoxelIndex::changed_since): the same values.
  void compute(const Pose& T_world_camera, const Vec3& target, std::vector<float>* out);
  /// Views whose ray-set features were kept / cast.
  std::size_t rays_kept() const { return rays_kept_; }
  std::size_t rays_cast() const { return rays_cast_; }

 private:
  struct Fruit;  // per fitted fruit: label consistency, seen fraction
  int fruit_of(const Vec3& target) const;
  void compute_rays(const Pose& T, const Vec3& target, std::vector<float>* out);  // the ray sets' features
  void compute_rest(const Pose& T, const Vec3& target, std::vector<float>* out);  // the others
  CameraIntrinsics intrinsics_;
  NbvParams nbv_;
  ViewFeatureParams params_;
  std::vector<std::unique_ptr<GainFunction>> gains_;
  std::vector<const GainFunction*> gain_ptrs_;  // gains_, as evaluate_all takes them
  std::vector<double> scores_;                  // one ray set's gains (scratch)
  std::vector<const RaySetEntry*> ray_sets_;
  const VoxelIndex* index_ = nullptr;
  std::unique_ptr<ViewEvaluator> eval_;
  ShapeFitCache cache_;
  std::vector<FittedFruit> fruits_;
  std::vector<Fruit> fruit_info_;
  std::vector<PredictedPoint> points_;
  std::vector<std::pair<Vec3, double>> fruit_spheres_;  // per fruit: a sphere holding its points_ (radius < 0: none)
  std::vector<char> fruit_out_of_view_;                  // per fruit, for the view being computed
  std::vector<float> weights_;  // refute rule: 1 or 0; fruit-probability rule beside it
  std::vector<float> fruit_weights_;
  std::size_t walk_capacity_ = 0;  // voxels a sight line may visit (the most any round needed)
  Pose T_now_ = Pose::Identity();
  // The ray sets' features of the views computed so far (a stop's rounds score the same
  // candidates again), with the bricks their rays read and the index's generation then.
  using ViewKey = std::array<std::uint64_t, 15>;  // the pose's 3x4 and the target, bit for bit
  struct ViewKeyHash {
    std::size_t operator()(const ViewKey& k) const;
  };
  struct RayFeatures {
    std::vector<float> values;
    std::vector<std::uint64_t> bricks;
    std::uint64_t generation = 0;
  };
  std::unordered_map<ViewKey, RayFeatures, ViewKeyHash> ray_features_;
  const VoxelIndex* ray_features_index_ = nullptr;
  std::vector<std::uint64_t> bricks_;  // scratch
  std::size_t rays_kept_ = 0, rays_cast_ = 0;
};

}  // namespace canopy::nbv
