#pragma once
// The semantic octree: an OctoMap tree (OcTreeBaseImpl) whose nodes carry a SemanticState.
//
// Only leaves carry meaning: a leaf at the finest depth is one voxel; a leaf higher up is a
// pruned block of identical voxels. A key with no leaf is unknown (never observed). Inner
// nodes' payloads are unspecified. All queries are const and allocation-free, so the
// next-best-view ray caster can call find() per voxel from several threads at once.

#include <octomap/AbstractOcTree.h>
#include <octomap/OcTreeBaseImpl.h>
#include <octomap/OcTreeDataNode.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/common/error.h"
#include "canopy/common/types.h"
#include "canopy/mapping/map_params.h"
#include "canopy/mapping/semantic_state.h"
#include "canopy/mapping/voxel_key.h"

namespace canopy::mapping {

/// Octree node holding one SemanticState (8-byte child pointer + 20-byte payload).
class SemanticNode : public octomap::OcTreeDataNode<SemanticState> {
 public:
  SemanticNode() : octomap::OcTreeDataNode<SemanticState>(SemanticState{}) {}
  const SemanticState& state() const { return value; }
  SemanticState& state() { return value; }

  // Structure edits that, unlike OcTreeBaseImpl's, do not touch the tree's node counter, so
  // disjoint subtrees can be edited from several threads; the caller fixes the count.
  /// Child i or nullptr.
  SemanticNode* child(unsigned i) const {
    return children ? static_cast<SemanticNode*>(children[i]) : nullptr;
  }
  bool has_children() const;
  /// Creates child i (which must not exist) with a fresh state.
  SemanticNode* make_child(unsigned i);
  /// Turns a pruned leaf into eight children carrying its state (8 nodes created).
  void expand();
  /// Replaces eight identical leaf children by this node (8 nodes deleted); false if not.
  bool collapse();
  /// Deletes every node below this one (the caller fixes the tree's node count).
  void delete_children();
};

/// One voxel update of a scan: a Morton-ordered key and what was seen there.
struct VoxelUpdate {
  static constexpr std::uint8_t kFree = 255;  ///< `label` of a pass-through.
  std::uint64_t code = 0;                     ///< morton_code(key); sort key of the batch.
  std::uint8_t label = kFree;                 ///< Observed class, or kFree.
};

/// Counters of one batch update.
struct UpdateCounts {
  std::size_t applied = 0;        ///< Voxel updates that changed a voxel.
  std::size_t saturated = 0;      ///< Updates skipped because the voxel could not change.
  std::size_t created = 0;        ///< Nodes allocated (new voxels and expansions).
  std::size_t pruned = 0;         ///< Inner nodes collapsed.
};

/// Leaf counts of a map.
struct VoxelCounts {
  std::size_t leaves = 0;          ///< Leaf nodes (pruned blocks count once).
  std::size_t voxels = 0;          ///< Known finest-level voxels (blocks expanded).
  std::size_t occupied = 0;        ///< Known voxels with p_occ > 0.5.
  std::size_t free = 0;            ///< Known voxels with p_occ <= 0.5.
  std::size_t target = 0;          ///< Occupied voxels whose most likely class is the target.
  std::size_t nodes = 0;           ///< All tree nodes.
  std::size_t memory_bytes = 0;    ///< Approximate heap use of the tree.
};

/// Probabilistic multi-class voxel map (SSMI rules) with OctoMap's addressing.
///
/// OctoMap's tree is a protected base: every change goes through the members below, which
/// bump revision(), so caches beside the tree (the NBV voxel index, the planner's collision
/// environment) cannot be left stale by a mutator that bypasses the counter.
class SemanticOcTree : protected octomap::OcTreeBaseImpl<SemanticNode, octomap::AbstractOcTree> {
  using Base = octomap::OcTreeBaseImpl<SemanticNode, octomap::AbstractOcTree>;

 public:
  // OctoMap's read-only queries.
  using Base::calcNumNodes;
  using Base::computeRayKeys;
  using Base::coordToKey;
  using Base::coordToKeyChecked;
  using Base::getNumLeafNodes;
  using Base::getResolution;
  using Base::getTreeDepth;
  using Base::keyToCoord;
  using Base::memoryUsage;
  using Base::size;
  /// Root node (read-only); the tree must be whole (nothing moved out by keep_x()).
  const SemanticNode* getRoot() const {
    if (!moved_.empty()) [[unlikely]] moved_out_walk();
    return root;
  }
  bool nodeHasChildren(const SemanticNode* node) const { return Base::nodeHasChildren(node); }
  const SemanticNode* getNodeChild(const SemanticNode* node, unsigned int i) const { return Base::getNodeChild(node, i); }
  /// Removes every voxel (the map becomes all unknown).
  void clear() {
    Base::clear();
    moved_.clear();
    moved_bytes_ = 0;
    windowed_ = false;
    ++revision_;
  }

  SemanticOcTree(const SemanticMapParams& params, const SemanticClasses& classes);
  SemanticOcTree(const SemanticOcTree& other);  ///< Deep copy.
  SemanticOcTree(SemanticOcTree&& other) noexcept;

  SemanticOcTree* create() const override { return new SemanticOcTree(params_, classes_); }
  std::string getTreeType() const override { return "SemanticOcTree"; }

  const SemanticMapParams& params() const { return params_; }
  const SemanticClasses& classes() const { return classes_; }
  int num_classes() const { return classes_.size(); }
  const UpdateRule& rule() const { return rule_; }
  /// Incremented by every change; lets caches beside the tree (a flat voxel index) notice.
  std::uint64_t revision() const { return revision_; }

  // --- Queries (const, thread-safe between updates) ------------------------------------
  /// State of the voxel with `key`, or nullptr when it is unknown. A key inside a subtree moved
  /// out by keep_x() is an internal error (CheckFailure), never "unknown".
  const SemanticState* find(const octomap::OcTreeKey& key) const {
    const SemanticNode* n = search(key);
    if (!n) return nullptr;
    if (n->state().count == kMovedOutMark) [[unlikely]] moved_out_read(key);
    return &n->state();
  }
  /// State of the voxel containing `p_world`, or nullptr when unknown or outside the tree.
  const SemanticState* find(const Vec3& p_world) const;
  /// Key of the voxel containing `p_world`; false outside the tree's range.
  bool key_of(const Vec3& p_world, octomap::OcTreeKey* key) const {
    return coordToKeyChecked(p_world.x(), p_world.y(), p_world.z(), *key);
  }
  /// Centre of a finest-level voxel.
  Vec3 center_of(const octomap::OcTreeKey& key) const {
    return {keyToCoord(key[0]), keyToCoord(key[1]), keyToCoord(key[2])};
  }
  /// True when the voxel containing `p_world` was never observed.
  bool is_unknown(const Vec3& p_world) const { return find(p_world) == nullptr; }
  /// p_occ at `p_world`; 0.5 when unknown.
  double occupancy(const Vec3& p_world) const;
  /// Entropy (nats) at `p_world`; unseen_entropy() when unknown.
  double entropy(const Vec3& p_world) const;
  /// Entropy of a never-observed voxel under params().unseen_logodds.
  double unseen_entropy() const { return unseen_entropy_; }
  /// Entropy of a voxel state over params().entropy_categories.
  double entropy_of(const SemanticState& s) const {
    return s.entropy(params_.entropy_categories, static_cast<int>(classes_.size()));
  }
  /// True when a state counts as a voxel of class `c`: occupied (p_occ > 0.5) and c is
  /// its most likely class.
  static bool is_class_voxel(const SemanticState& s, int c) {
    return s.most_likely_class() == c && s.occupancy_logodds() > 0.f;
  }

  /// Calls f(key, depth, state) for every leaf; `key` is the leaf's key at `depth` (a block
  /// of 2^(16 - depth) voxels per axis when depth < 16), in depth-first order.
  template <typename F>
  void for_each_leaf(F&& f) const {
    const octomap::OcTreeKey lo(0, 0, 0), hi(0xffff, 0xffff, 0xffff);
    if (root) for_each_leaf_in_keys_recurs(root, octomap::OcTreeKey(tree_max_val, tree_max_val, tree_max_val), 0, lo, hi, f);
  }
  /// for_each_leaf over the whole tree, the subtrees moved out by keep_x() included: each is
  /// decompressed for the walk (the tree is not changed), so f sees the leaves, keys, depths
  /// and order of the tree without keep_x(). One subtree's bytes held at a time.
  template <typename F>
  void for_each_leaf_all(F&& f) const {
    if (root) for_each_leaf_all_recurs(root, octomap::OcTreeKey(tree_max_val, tree_max_val, tree_max_val), 0, 0, f);
  }
  /// Calls f(key, state) for every finest-level voxel of every leaf whose state passes
  /// keep(state); pruned blocks are expanded into their voxels (only when kept, so large free
  /// blocks cost nothing when the predicate rejects them).
  template <typename Keep, typename F>
  void for_each_voxel_if(Keep&& keep, F&& f) const {
    for_each_leaf([&](const octomap::OcTreeKey& key, unsigned depth, const SemanticState& s) {
      if (keep(s)) for_each_voxel_of_leaf(key, depth, s, f);
    });
  }
  /// for_each_voxel_if restricted to the leaves that overlap the key box [lo, hi] (inclusive):
  /// the same voxels in the same order as for_each_voxel_if, less those of leaves wholly
  /// outside the box (a pruned block overlapping it is expanded whole), at a cost that depends
  /// on the box, not on the map.
  template <typename Keep, typename F>
  void for_each_voxel_in_keys_if(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi, Keep&& keep, F&& f) const {
    auto leaf = [&](const octomap::OcTreeKey& key, unsigned depth, const SemanticState& s) {
      if (keep(s)) for_each_voxel_of_leaf(key, depth, s, f);
    };
    if (root) for_each_leaf_in_keys_recurs(root, octomap::OcTreeKey(tree_max_val, tree_max_val, tree_max_val), 0, lo, hi, leaf);
  }
  /// Leaf and voxel counts (target = classes().target_index()), the moved-out subtrees' included
  /// (keep_x()); memory_bytes is memory_bytes().
  VoxelCounts counts() const;
  /// Heap use: the tree's nodes (memoryUsage()) and the moved-out subtrees' bytes.
  std::size_t memory_bytes() const;

  // --- The far part kept compactly (issue 49) --------------------------------------------
  /// Moves every subtree of 64 voxels a side (tree depth 10) that has children and lies wholly
  /// outside x [x_lo_m, x_hi_m] out of the tree, as compressed bytes beside its counts, and
  /// puts back, as they were, the moved-out subtrees that the stretch holds again. A moved-out
  /// subtree's node stays in the tree as a childless stub whose state no voxel can have, so the
  /// nodes around it answer and change as in the whole tree (a stub is never equal to a leaf,
  /// so no parent is pruned over it). A read that reaches a stub (find(), the leaf walks,
  /// getRoot()) is an internal error; an update there puts its subtree back first, so updates
  /// are the whole tree's. counts() and memory_bytes() cover everything. Not thread-safe: call
  /// it between updates, with no reader running.
  void keep_x(double x_lo_m, double x_hi_m);
  /// Every subtree back: the tree is the one that took every change without keep_x().
  void keep_all();
  /// Subtrees moved out now.
  std::size_t moved_out() const { return moved_.size(); }
  /// Bytes of the moved-out subtrees (compressed).
  std::size_t moved_out_bytes() const { return moved_bytes_; }
  /// The depth of the subtrees keep_x() moves (64 voxels a side).
  static constexpr unsigned kMovedDepth = 10;

  // --- Updates ---------------------------------------------------------------------------
  /// Applies one hit of class `c` to the voxel `key` (creating it when unknown).
  void update_hit(const octomap::OcTreeKey& key, int c);
  /// Applies one pass-through to the voxel `key`.
  void update_free(const octomap::OcTreeKey& key);
  /// Applies a batch sorted by code with unique codes, descending the tree once for all of
  /// it; prunes touched nodes when params().prune. Order-independent by construction. When
  /// `occupancy` is given it receives one byte per update: kOccupiedBefore / kOccupiedAfter
  /// (occupancy log-odds > 0 before and after the update), so callers that mirror the occupied
  /// voxels need not look each voxel up again.
  UpdateCounts apply_sorted_updates(const std::vector<VoxelUpdate>& updates,
                                    std::vector<std::uint8_t>* occupancy = nullptr);
  static constexpr std::uint8_t kOccupiedBefore = 1, kOccupiedAfter = 2;

  /// True when both trees have identical structure, payloads, params and classes (both whole:
  /// nothing moved out).
  bool identical(const SemanticOcTree& other) const;

  /// For map_io: the root pointer and node creation (file loading builds the tree directly).
  SemanticNode* mutable_root() { return root; }
  SemanticNode* create_root();
  /// After building the tree node by node: sets the node count and the revision.
  void set_loaded_state(std::size_t nodes, std::uint64_t revision) {
    CANOPY_CHECK(moved_.empty(), "SemanticOcTree: loaded over moved-out subtrees");
    tree_size = nodes;
    size_changed = true;
    revision_ = revision;
  }

 private:
  // f(key, s) for each finest-level voxel of a leaf (a pruned block's key is its centre key).
  template <typename F>
  void for_each_voxel_of_leaf(const octomap::OcTreeKey& key, unsigned depth, const SemanticState& s, F& f) const {
    if (depth == tree_depth) {
      f(key, s);
      return;
    }
    const int half = 1 << (tree_depth - 1 - depth);
    for (int z = -half; z < half; ++z)
      for (int y = -half; y < half; ++y)
        for (int x = -half; x < half; ++x)
          f(octomap::OcTreeKey(static_cast<octomap::key_type>(key[0] + x), static_cast<octomap::key_type>(key[1] + y),
                               static_cast<octomap::key_type>(key[2] + z)),
            s);
  }
  // The children present in `mask` (bit i: child i) of the node with key `key` at `depth`:
  // g(i, child key), in child order (the walks' depth-first order).
  template <typename G>
  void for_each_child_key(std::uint8_t mask, const octomap::OcTreeKey& key, unsigned depth, G&& g) const {
    const unsigned short half = static_cast<unsigned short>(tree_max_val >> (depth + 1));
    for (unsigned i = 0; i < 8; ++i) {
      if (!(mask & (1u << i))) continue;
      octomap::OcTreeKey k = key;
      octomap::computeChildKey(i, half, key, k);
      g(i, k);
    }
  }
  std::uint8_t child_mask(const SemanticNode* node) const {
    std::uint8_t mask = 0;
    for (unsigned i = 0; i < 8; ++i)
      if (nodeChildExists(node, i)) mask |= std::uint8_t(1u << i);
    return mask;
  }
  template <typename F>
  void for_each_leaf_all_recurs(const SemanticNode* node, const octomap::OcTreeKey& key, unsigned depth,
                                std::uint64_t code, F& f) const {
    if (!nodeHasChildren(node)) {
      if (node->state().count == kMovedOutMark) [[unlikely]] {
        const std::string raw = moved_out_bytes(code);
        std::size_t at = 0;
        walk_moved(raw, &at, key, depth, f);
        return;
      }
      f(key, depth, node->state());
      return;
    }
    for_each_child_key(child_mask(node), key, depth, [&](unsigned i, const octomap::OcTreeKey& k) {
      for_each_leaf_all_recurs(getNodeChild(node, i), k, depth + 1, (code << 3) | i, f);
    });
  }
  // A moved-out subtree's nodes as write_moved wrote them (pre-order: state, children mask).
  template <typename F>
  void walk_moved(const std::string& raw, std::size_t* at, const octomap::OcTreeKey& key, unsigned depth, F& f) const {
    CANOPY_CHECK(*at + sizeof(SemanticState) + 1 <= raw.size(), "semantic map: a moved-out subtree read past its end");
    SemanticState state;
    std::memcpy(&state, raw.data() + *at, sizeof(SemanticState));
    const auto mask = static_cast<std::uint8_t>(raw[*at + sizeof(SemanticState)]);
    *at += sizeof(SemanticState) + 1;
    if (mask == 0) {
      f(key, depth, static_cast<const SemanticState&>(state));
      return;
    }
    for_each_child_key(mask, key, depth, [&](unsigned, const octomap::OcTreeKey& k) { walk_moved(raw, at, k, depth + 1, f); });
  }
  // The decompressed bytes of the subtree moved out at window code `code`.
  std::string moved_out_bytes(std::uint64_t code) const;
  template <typename F>
  void for_each_leaf_in_keys_recurs(const SemanticNode* node, const octomap::OcTreeKey& key, unsigned depth,
                                    const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi, F& f) const {
    // The node covers keys [key - side / 2, key + side / 2 - 1] on each axis.
    const int side = 1 << (tree_depth - depth);
    for (int a = 0; a < 3; ++a) {
      const int first = int(key[a]) - side / 2, last = first + side - 1;
      if (last < int(lo[a]) || first > int(hi[a])) return;
    }
    if (!nodeHasChildren(node)) {
      if (node->state().count == kMovedOutMark) [[unlikely]] moved_out_read(key);
      f(key, depth, node->state());
      return;
    }
    for_each_child_key(child_mask(node), key, depth, [&](unsigned i, const octomap::OcTreeKey& k) {
      for_each_leaf_in_keys_recurs(getNodeChild(node, i), k, depth + 1, lo, hi, f);
    });
  }
  // A stub's state (keep_x()): a count no voxel has (at most SemanticState::kSlots).
  static constexpr std::uint8_t kMovedOutMark = 0xfe;
  // A moved-out subtree: its nodes pre-order (state, children mask), zstd-compressed, and its
  // counts (nodes: the subtree's, its root included).
  struct MovedOut {
    std::string bytes;
    VoxelCounts counts;
  };
  [[noreturn]] void moved_out_read(const octomap::OcTreeKey& key) const;
  [[noreturn]] void moved_out_walk() const;
  // The depth-10 node with window code `code` (morton code >> 18), or nullptr.
  SemanticNode* window_node(std::uint64_t code) const;
  void move_out(SemanticNode* node, std::uint64_t code);
  void put_back(std::uint64_t code);
  void move_out_recurs(SemanticNode* node, unsigned depth, std::uint64_t code, unsigned lo, unsigned hi);
  // Puts back the moved-out subtrees that a sorted batch of updates reaches.
  void put_back_updated(const std::vector<VoxelUpdate>& updates);

  void apply_range(SemanticNode* top, unsigned top_depth, const VoxelUpdate* begin, const VoxelUpdate* end,
                   bool collapse_top, bool top_is_fresh, UpdateCounts& counts, std::uint8_t* occupancy);

  SemanticMapParams params_;
  SemanticClasses classes_;
  UpdateRule rule_;
  double unseen_entropy_ = 0.0;
  std::uint64_t revision_ = 0;
  // keep_x(): window x [window_lo_, window_hi_] (64-voxel units) held; the moved-out subtrees
  // by window code.
  bool windowed_ = false;
  unsigned window_lo_ = 0, window_hi_ = 0;
  std::unordered_map<std::uint64_t, MovedOut> moved_;
  std::size_t moved_bytes_ = 0;
};

}  // namespace canopy::mapping
