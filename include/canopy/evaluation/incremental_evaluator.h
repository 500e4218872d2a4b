#pragma once
// Map metrics kept up to date view by view: after a scan only what the scan's voxel updates can
// change is scored again, so a view costs the same whatever the size of the world and the map.
//
//  - coverage: a surface point's covered flag (per rule) can only change when a fruit voxel
//    within delta S of it appears or disappears; only those points are tested again, against a
//    hash of the current fruit voxels (the same squared distance, summed in the same order, as
//    the reference's KD-tree query);
//  - entropy: a fruit's entropies are summed again when a changed voxel lies in its paper box
//    or its prototype sphere's box;
//  - fruit voxels and their voxel precision (on a true fruit or not) are kept in a hash;
//  - detection: the fruit voxels' connected components are kept; only those a change touches
//    (a voxel of theirs left, or a new voxel next to them) are flooded again, and each cluster
//    is computed as fruit_clusters computes it (members in grid-cell order).
// The result equals evaluate_map() bit for bit, except MapMetrics::counts (the map's leaf
// counts need a full pass: call SemanticOcTree::counts() when they are wanted).

#include <cstdint>
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

#include "canopy/evaluation/fruit_metrics.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/world/ground_truth.h"

namespace canopy {
class PointKdTree;
}

namespace canopy::evaluation {

class TrueFruitSurface;

/// Keeps a map's metrics up to date from the voxel updates applied to it.
class IncrementalEvaluator {
 public:
  /// Keeps references to `truth` (it must outlive the evaluator).
  IncrementalEvaluator(const world::GroundTruth& truth, const MetricsParams& params);
  ~IncrementalEvaluator();
  IncrementalEvaluator(const IncrementalEvaluator&) = delete;
  IncrementalEvaluator& operator=(const IncrementalEvaluator&) = delete;

  /// The metrics of `map` after the voxel updates `changed` (sorted or not; e.g.
  /// ScanInserter::last_updates()) were applied to it. The first call, a call with another map,
  /// or one after reset() scores the whole map. Between calls the map may change only through
  /// updates passed here.
  const MapMetrics& update(const SemanticOcTree& map, const std::vector<mapping::VoxelUpdate>& changed);
  /// The next update() scores the whole map.
  void reset() { map_ = nullptr; }
  /// The metrics of the last update().
  const MapMetrics& metrics() const { return metrics_; }
  /// Whether the last update() scored `map` (metrics() are then `map`'s, provided the map has
  /// changed only through the updates passed since, as update() requires).
  bool follows(const SemanticOcTree& map) const { return map_ == &map && resolution_ == map.getResolution(); }
  /// Surface points and fruits scored again by the last update() (for benchmarks and tests).
  std::size_t last_rescored_points() const { return last_points_; }
  std::size_t last_rescored_fruits() const { return last_fruits_; }
  /// Approximate heap use: the truth's points and their trees, the fruits' entropy keys and
  /// the fruit voxels (`canopy bench mission`).
  std::size_t memory_bytes() const;

 private:
  enum : std::uint8_t { kPaper = 1, kPrototype = 2, kOnFruit = 4 };
  void score_all(const SemanticOcTree& map);
  void index_fruit_boxes(const SemanticOcTree& map);
  std::uint8_t classify(const SemanticOcTree& map, const octomap::OcTreeKey& key, const mapping::SemanticState* s) const;
  void set_voxel(std::uint64_t code, std::uint8_t flags, const Vec3& centre);
  std::uint8_t covered_flags(const SemanticOcTree& map, const Vec3& p) const;
  void rescore_point(const SemanticOcTree& map, std::size_t i);
  void finish(const SemanticOcTree& map);
  const std::vector<Vec3>& points() const;
  void update_components(const SemanticOcTree& map);

  /// A connected component (26-neighbourhood) of the rule's fruit voxels.
  struct Component {
    std::vector<std::uint64_t> codes;
    std::int64_t first_cell = 0;  ///< Smallest fruit_cell of its members: its place in the output.
    FruitCluster cluster;
  };

  const world::GroundTruth& truth_;
  MetricsParams params_;
  const SemanticOcTree* map_ = nullptr;
  std::uint64_t revision_ = 0;
  double resolution_ = 0.0;

  std::vector<const world::FruitTruth*> fruits_;  ///< Target fruits, in truth order.
  std::vector<Vec3> centroids_;
  std::vector<std::uint32_t> point_fruit_;        ///< Index into fruits_ of each point (point_tree_'s).
  std::vector<std::uint8_t> point_covered_;       ///< kPaper | kPrototype.
  /// All target surface points, fruit by fruit (points()), held once: the coverage's
  /// neighbours and surface_'s on-fruit test both search this tree.
  std::unique_ptr<PointKdTree> point_tree_;
  std::unique_ptr<TrueFruitSurface> surface_;
  /// (Morton code, fruit) for every voxel key in a fruit's entropy boxes, sorted.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> fruit_keys_;

  std::unordered_map<std::uint64_t, std::uint8_t> voxels_;  ///< Fruit voxels: kPaper [| kPrototype] | kOnFruit.
  std::size_t paper_voxels_ = 0, prototype_voxels_ = 0;
  std::size_t paper_on_fruit_ = 0, prototype_on_fruit_ = 0;

  // Detection: components of the rule's fruit voxels, and the voxels that joined or left the
  // rule's set since the last update.
  std::unordered_map<std::uint64_t, std::uint32_t> component_of_;
  std::unordered_map<std::uint32_t, Component> components_;
  std::map<std::int64_t, std::uint32_t> component_order_;  ///< first_cell -> component
  std::uint32_t next_component_ = 0;
  std::vector<std::uint64_t> joined_, left_;

  MapMetrics metrics_;
  std::size_t last_points_ = 0, last_fruits_ = 0;
};

}  // namespace canopy::evaluation
