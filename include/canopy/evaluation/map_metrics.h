#pragma once
// Map quality against the world's ground truth (paper Experiments; docs/background/evaluation.md).
// Only target (ripe) fruits count. Two evaluation rules, both always computed:
//  - paper: a ground-truth surface point is covered when its nearest fruit voxel centre
//    (occupied, most likely class = target) lies within delta S; the fruit entropy is the sum
//    of H over the voxels whose centres lie in a cube of side L around the fruit's centre,
//    H over the map's entropy categories, unknown voxels at SSMI's unseen prior.
//  - prototype (the released code's): a fruit voxel must also have target log-odds above
//    prototype_min_logodds (1.0: one observation is not enough); the entropy is summed over
//    voxels whose centres lie within prototype_entropy_radius_m (0.05 m) of the fruit's
//    centroid (the mean of its surface points), leaving out known voxels whose likeliest
//    category is free, with H over the released code's 5-entry vector (prototype categories)
//    whatever the map's setting.
// `rule` picks which of the two fills MapMetrics::coverage / total_entropy (reports default
// to prototype: it produced the paper's figures); both are in to_json(). Nearest voxels are
// found with a nanoflann KD-tree over the voxel centres.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/evaluation/fruit_metrics.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/world/ground_truth.h"

namespace canopy::evaluation {

using mapping::SemanticOcTree;
using mapping::VoxelCounts;

/// Which evaluation rule the headline figures follow.
enum class EvaluationRule { kPrototype, kPaper };
inline constexpr EnumName<EvaluationRule> kEvaluationRuleNames[] = {{EvaluationRule::kPrototype, "prototype"},
                                                                    {EvaluationRule::kPaper, "paper"}};
/// "prototype" / "paper".
std::string to_string(EvaluationRule r);

/// Evaluation settings (paper Table I, docs/background/evaluation.md).
struct MetricsParams {
  EvaluationRule rule = EvaluationRule::kPrototype;
  double coverage_distance_m = 0.015;
  double entropy_box_m = 0.1;
  double prototype_min_logodds = 1.0;
  double prototype_entropy_radius_m = 0.05;
  double match_size_fraction = 0.5;
  int detection_min_voxels = 1;
  mapping::ShapeFitParams shape_fit;

  template <class A>
  void visit(A& a) {
    a.choice("rule", rule, kEvaluationRuleNames, "Rule of the headline coverage and entropy (both are always written)");
    a("coverage_distance_m", coverage_distance_m, limits::positive(),
      "delta S: a surface point is covered when a fruit voxel centre lies this close [m]");
    a("entropy_box_m", entropy_box_m, limits::above_up_to(0.0, 2.0),
      "L: side of the cube around each fruit's centre summed by the paper rule's entropy [m]");
    a("prototype_min_logodds", prototype_min_logodds, limits::finite(),
      "Prototype rule: a fruit voxel needs target log-odds above this");
    a("prototype_entropy_radius_m", prototype_entropy_radius_m, limits::above_up_to(0.0, 1.0),
      "Prototype rule: radius of the entropy sphere around each fruit's centroid [m]");
    a("match_size_fraction", match_size_fraction, limits::above_up_to(0.0, 5.0),
      "Fruit detection: a cluster matches a fruit when its centroid lies within this fraction of the fruit's size");
    a("detection_min_voxels", detection_min_voxels, limits::in(1, 1000000),
      "Fruit detection: clusters of fewer fruit voxels are not detections");
    a.section("shape_fit", shape_fit, "Fruit detection: each cluster's shape fit (docs/shape.md)");
  }
  bool operator==(const MetricsParams& o) const { return same_params(*this, o); }
};

/// Coverage and entropy of one fruit or one map under one rule.
struct RuleScores {
  std::size_t covered = 0;      ///< Surface points with a fruit voxel within delta S.
  double coverage = 0.0;        ///< covered / points (0 without points).
  double entropy = 0.0;         ///< [nats]
  std::size_t voxels = 0;       ///< Voxels summed into the entropy.
  std::size_t unknown = 0;      ///< Of which never observed.
};

/// Scores of one target fruit.
struct FruitMetrics {
  int instance_id = 0;
  int plant_index = 0;
  std::size_t points = 0;       ///< Ground-truth surface points.
  double coverage = 0.0;        ///< Under MetricsParams::rule.
  double entropy = 0.0;         ///< Under MetricsParams::rule [nats].
  RuleScores paper, prototype;
};

/// Scores of a whole map (target fruits only).
struct MapMetrics {
  EvaluationRule rule = EvaluationRule::kPrototype;
  double coverage = 0.0;        ///< Covered points / all points over all target fruits, under `rule`.
  double total_entropy = 0.0;   ///< Sum of the target fruits' entropies under `rule` [nats].
  std::size_t points = 0;
  RuleScores paper, prototype;  ///< Both rules over the whole map.
  std::size_t fruit_voxels_paper = 0;      ///< Voxels in the paper rule's coverage KD-tree.
  std::size_t fruit_voxels_prototype = 0;  ///< Of which pass the prototype's log-odds test.
  std::size_t non_target_fruits = 0;       ///< Unripe fruits left out.
  std::vector<FruitMetrics> fruits;
  VoxelCounts counts;
  /// Shares of the target fruits whose coverage (under `rule`) reaches 50 % and 80 %.
  double fruits_sc50 = 0.0, fruits_sc80 = 0.0;
  /// Fruit detection and shape, of the fruit voxels counted under `rule` (fruit_metrics.h).
  FruitDetection detection;
  /// Fruit voxels (under `rule`) on a true fruit and elsewhere.
  FruitVoxelPrecision voxel_precision;

  nlohmann::json to_json() const;
};


/// Scores `map` against `truth` (the map's target class is the fruit class): a full pass over
/// the map and every surface point (the reference; missions use IncrementalEvaluator).
MapMetrics evaluate_map(const SemanticOcTree& map, const world::GroundTruth& truth, const MetricsParams& params);

// Pieces shared by evaluate_map and IncrementalEvaluator (incremental_evaluator.h).
/// Mean of a fruit's surface points (its centre when it has none), summed in point order.
Vec3 surface_centroid(const world::FruitTruth& f);
/// A fruit's entropies under both rules (paper box around f.center, prototype sphere around
/// `centroid`) into fm->paper and fm->prototype.
void score_fruit_entropy(const SemanticOcTree& map, const world::FruitTruth& f, const Vec3& centroid,
                         const MetricsParams& params, FruitMetrics* fm);
/// From the per-fruit covered counts and entropies of m->fruits: per-fruit coverage, the
/// totals over fruits (in fruit order), the headline figures under `rule`, fruits_sc50/80.
void summarize_fruits(MapMetrics* m, EvaluationRule rule);

/// One target-fruit surface point not yet covered under MetricsParams::rule.
struct UncoveredPoint {
  Vec3 position = Vec3::Zero();
  int instance_id = 0;
  /// Its index in target_surface_points() of the same truth.
  std::size_t index = 0;
};

/// Every target fruit's surface points, in fruit then point order (what
/// uncovered_target_points() picks from; UncoveredPoint::index points into it).
std::vector<Vec3> target_surface_points(const world::GroundTruth& truth);

/// The target-fruit surface points evaluate_map() counts as not covered under params.rule
/// (points - covered of the same rule), in fruit then point order: what a view can still add.
std::vector<UncoveredPoint> uncovered_target_points(const SemanticOcTree& map, const world::GroundTruth& truth,
                                                    const MetricsParams& params);

/// Entropy sum over the voxels whose centres lie in the axis-aligned box [lo, hi]
/// (unknown voxels at the unseen entropy); counts go to *voxels and *unknown when given.
double box_entropy(const SemanticOcTree& map, const Vec3& lo, const Vec3& hi, std::size_t* voxels = nullptr,
                   std::size_t* unknown = nullptr);

/// The prototype's fruit entropy: voxels whose centres lie within `radius` of `center`, known
/// voxels whose likeliest category is free left out, H over the prototype categories.
double prototype_sphere_entropy(const SemanticOcTree& map, const Vec3& center, double radius,
                                std::size_t* voxels = nullptr, std::size_t* unknown = nullptr);

}  // namespace canopy::evaluation
