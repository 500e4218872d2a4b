#pragma once
// Map quality against the world's ground truth (paper Experiments; FACTS.md section 8):
//  - surface coverage: the fraction of ground-truth fruit surface points whose nearest
//    target-class voxel centre (occupied, most likely class = target) is within delta S,
//    overall and per fruit (nanoflann KD-tree over the voxel centres);
//  - total fruit entropy: the sum over fruits of the entropies of the voxels whose centres lie
//    in a cube of side L around the fruit's centre. Unknown voxels count with the entropy of
//    SSMI's unseen prior (SemanticOcTree::unseen_entropy, ~1.61 nats), so observing a box
//    always lowers it. Overlapping boxes count once per fruit.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "canopy/common/yaml_reader.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/world/ground_truth.h"

namespace canopy::mapping {

/// Evaluation settings (paper Table I).
struct MetricsParams {
  double coverage_distance_m = 0.015;  ///< delta S: a surface point is covered within this.
  double entropy_box_m = 0.1;          ///< L: side of the cube around each fruit's centre.

  static MetricsParams from_yaml(YamlReader& y);
  YAML::Node to_yaml() const;
  bool operator==(const MetricsParams& o) const {
    return coverage_distance_m == o.coverage_distance_m && entropy_box_m == o.entropy_box_m;
  }
};

/// Scores of one ground-truth fruit.
struct FruitMetrics {
  int instance_id = 0;
  int plant_index = 0;
  std::size_t points = 0;       ///< Ground-truth surface points.
  std::size_t covered = 0;      ///< Points with a target voxel within delta S.
  double coverage = 0.0;        ///< covered / points (0 when the fruit has no points).
  double entropy = 0.0;         ///< Sum of voxel entropies in the fruit's box [nats].
  std::size_t box_voxels = 0;   ///< Voxels in the box.
  std::size_t box_unknown = 0;  ///< Of which never observed.
};

/// Scores of a whole map.
struct MapMetrics {
  double coverage = 0.0;        ///< Covered points / all points, over all fruits.
  std::size_t points = 0;
  std::size_t covered = 0;
  double total_entropy = 0.0;   ///< Sum of the fruits' box entropies [nats].
  std::size_t target_voxels = 0;  ///< Voxels in the coverage KD-tree.
  std::vector<FruitMetrics> fruits;
  VoxelCounts counts;

  nlohmann::json to_json() const;
};

/// Centres of all target-class voxels (pruned blocks expanded), in leaf order.
std::vector<Vec3> class_voxel_centers(const SemanticOcTree& map, int class_index);

/// Scores `map` against `truth` (the map's target class is the fruit class).
MapMetrics evaluate_map(const SemanticOcTree& map, const world::GroundTruth& truth, const MetricsParams& params);

/// Entropy sum over the voxels whose centres lie in the axis-aligned box [lo, hi]
/// (unknown voxels at the unseen entropy); counts go to *voxels and *unknown when given.
double box_entropy(const SemanticOcTree& map, const Vec3& lo, const Vec3& hi, std::size_t* voxels = nullptr,
                   std::size_t* unknown = nullptr);

}  // namespace canopy::mapping
