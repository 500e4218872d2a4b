#pragma once
// Map metrics kept up to date view by view: after a scan only what the scan's voxel updates can
// change is scored again, so a view costs the same whatever the size of the world and the map.
//
//  - coverage: a surface point's covered flag (per rule) can only change when a fruit voxel
//    within delta S of it appears or disappears; only those points are tested again, against the
//    current fruit voxels (the same squared distance, summed in the same order, as
//    the reference's KD-tree query);
//  - entropy: a fruit's entropies are summed again when a changed voxel lies in its paper box
//    or its prototype sphere's box;
//  - fruit voxels and their voxel precision (on a true fruit or not) are kept in bricks
//    (brick_flags.h);
//  - detection: the fruit voxels' connected components are kept; only those a change touches
//    (a voxel of theirs left, or a new voxel next to them) are flooded again, and each cluster
//    is computed as fruit_clusters computes it (members in grid-cell order).
// The result equals evaluate_map() bit for bit, except MapMetrics::counts (the map's leaf
// counts need a full pass: call SemanticOcTree::counts() when they are wanted).
//
// Memory is bounded by the stretch a scan reaches, not by the world (issue 49): the true
// surface points are read from the truth, not copied; a k-d tree holds only the points of the
// fruits along the stretch of x the updates reach (plus window_pad_m each side) and is built
// again when an update reaches beyond it (every query then lies inside it with its whole
// radius, so its answers are the whole tree's); the fruits' entropy boxes are kept as key
// ranges on a coarse grid, not as every key in them.

#include <cstdint>
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

#include "canopy/evaluation/brick_flags.h"
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
  /// Points held beyond the stretch an update reaches, each side along x (m).
  static constexpr double kWindowPadM = 2.0;
  /// Keeps references to `truth` (it must outlive the evaluator). `window_pad_m` > 0: see
  /// kWindowPadM (tests pass a small one to move the window often).
  IncrementalEvaluator(const world::GroundTruth& truth, const MetricsParams& params,
                       double window_pad_m = kWindowPadM);
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
  /// True surface points in the k-d tree now, and how often it was built (tests, benchmarks).
  std::size_t window_points() const;
  std::size_t window_builds() const { return window_builds_; }
  /// Approximate heap use: the points' flags, the window's tree, the fruits' entropy boxes
  /// and the fruit voxels (`canopy bench mission`; the truth's points are the world's).
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
  /// The index of target surface point i's fruit (points fruit by fruit, in truth order).
  std::uint32_t fruit_of(std::size_t i) const;
  /// The window's tree holds every point with lo <= x <= hi (built again when it does not).
  void hold_x(double lo, double hi);
  /// Indices (fruit by fruit, in truth order) of the points within `radius` of `q`, appended; q +- radius held.
  void points_within(const Vec3& q, double radius, std::vector<std::uint32_t>* out);
  /// The boxes of one grid cell (box_cells_' entries), the last cell mark_dirty_fruits() looked up.
  struct CellRange {
    std::uint64_t cell = ~std::uint64_t(0);  // no cell
    std::vector<std::pair<std::uint64_t, std::uint32_t>>::const_iterator first, last;
  };
  void mark_dirty_fruits(std::uint64_t code, CellRange* last, std::vector<char>* dirty) const;
  void update_components(const SemanticOcTree& map);

  /// A fruit's entropy box as the (clamped) key range its voxels fill; two per fruit.
  struct KeyBox {
    int lo[3], hi[3];
  };
  static constexpr int kBoxCellShift = 4;  ///< Grid cells of 16 keys a side index the boxes.

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

  double window_pad_m_;
  std::vector<const world::FruitTruth*> fruits_;  ///< Target fruits, in truth order.
  std::vector<Vec3> centroids_;
  std::vector<std::size_t> first_point_;          ///< fruits_.size() + 1 offsets: fruit f's points are [first_point_[f], first_point_[f + 1]).
  std::vector<double> fruit_x_lo_, fruit_x_hi_;   ///< Each fruit's points' extent along x.
  std::vector<std::uint8_t> point_covered_;       ///< kPaper | kPrototype.
  /// The window: the points of the fruits reaching into [window_lo_, window_hi_] (indices into
  /// the points, fruit by fruit, beside them); the coverage's neighbours and surface_'s on-fruit test search it.
  double window_lo_ = 0.0, window_hi_ = -1.0;
  std::unique_ptr<PointKdTree> window_tree_;
  std::vector<std::uint32_t> window_index_;
  std::vector<std::pair<std::size_t, double>> near_;  ///< points_within()'s search, reused.
  std::size_t window_builds_ = 0;
  std::unique_ptr<TrueFruitSurface> surface_;
  double reach_m_ = 0.0;  ///< The farthest either search reads from its query.
  std::vector<KeyBox> fruit_boxes_;                                ///< 2 i, 2 i + 1: fruit i's.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> box_cells_;  ///< (cell, box), sorted.

  BrickFlags voxels_;  ///< Fruit voxels: kPaper [| kPrototype] | kOnFruit.
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
