#pragma once
// The collision environment's octree with the node surgery that moves far subtrees out as
// compact bytes and puts them back exactly (CollisionEnvironment::keep_x, issue 49). Private to
// motion/collision.cpp.

#include <octomap/OcTree.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::motion {

namespace env_tree {  // named: CollisionEnvironment::Impl holds an EnvTree

// A node's children array (protected in OctoMap's nodes; a pointer to member named through a
// derived class reaches it legally), to unlink a subtree without OctoMap's deleteNodeChild,
// which leaves a deleted node's own children behind.
struct NodeChildren : octomap::OcTreeNode {
  static constexpr auto member() { return &NodeChildren::children; }
};
constexpr auto kChildren = NodeChildren::member();

// The environment's tree, with the node surgery that moves far subtrees out and back
// (CollisionEnvironment::keep_x).
class EnvTree : public octomap::OcTree {
 public:
  explicit EnvTree(double resolution) : octomap::OcTree(resolution) {}

  // The subtrees of `window_depth` nodes wholly outside node x [lo, hi] and with children are
  // written to `out` (by node code) and removed; inner nodes left without a child go too, and
  // the others' values are the maximum of their children's again, as setNodeValue keeps them.
  // Leaves (pruned blocks) are kept. Returns the nodes removed.
  template <class Out>
  std::size_t drop_outside(unsigned window_depth, unsigned lo, unsigned hi, Out&& out) {
    if (!root) return 0;
    const std::size_t before = tree_size;
    if (drop_recurs(root, 0, 0, 0, 0, window_depth, lo, hi, out) == kEmptied) {
      deleteNodeRecurs(root);
      root = nullptr;
      tree_size = 0;
    }
    size_changed = true;
    return before - tree_size;
  }

  // Puts the subtree `bytes` back as the node of `window_depth` with node coordinates
  // (ix, iy, iz), creating the path to it; the path's values are the maximum of their
  // children's again.
  void restore(unsigned window_depth, unsigned ix, unsigned iy, unsigned iz, const std::vector<std::uint8_t>& bytes) {
    const unsigned shift = tree_depth - window_depth;
    const octomap::OcTreeKey key(static_cast<octomap::key_type>(ix << shift), static_cast<octomap::key_type>(iy << shift),
                                 static_cast<octomap::key_type>(iz << shift));
    bool fresh = false;  // `node` made here (no children yet, not a pruned block)
    if (!root) {
      root = new octomap::OcTreeNode();
      ++tree_size;
      fresh = true;
    }
    std::vector<octomap::OcTreeNode*> path{root};
    octomap::OcTreeNode* node = root;
    for (unsigned depth = 0; depth + 1 < window_depth; ++depth) {
      const unsigned i = octomap::computeChildIdx(key, int(tree_depth - 1 - depth));
      if (!nodeChildExists(node, i)) {
        CANOPY_CHECK(fresh || nodeHasChildren(node), "collision environment: a pruned block over a moved-out subtree");
        createNodeChild(node, i);
        fresh = true;
      } else {
        fresh = false;
      }
      node = getNodeChild(node, i);
      path.push_back(node);
    }
    const unsigned i = octomap::computeChildIdx(key, int(tree_depth - window_depth));
    CANOPY_CHECK(!nodeChildExists(node, i), "collision environment: a moved-out subtree is in the tree");
    std::size_t at = 0;
    read_recurs(createNodeChild(node, i), bytes, &at);
    CANOPY_CHECK(at == bytes.size(), "collision environment: a moved-out subtree read short");
    for (std::size_t k = path.size(); k-- > 0;) path[k]->updateOccupancyChildren();
    size_changed = true;
  }

 private:
  enum Dropped { kKept, kChanged, kEmptied };

  template <class Out>
  Dropped drop_recurs(octomap::OcTreeNode* node, unsigned depth, unsigned x0, unsigned y0, unsigned z0,
                      unsigned window_depth, unsigned lo, unsigned hi, Out& out) {
    // `node` covers keys [x0, x0 + side) per axis; its children [x0, x0 + half) and [x0 + half, x0 + side).
    const unsigned half = 1u << (tree_depth - depth - 1), shift = tree_depth - window_depth;
    bool changed = false;
    for (unsigned i = 0; i < 8; ++i) {
      if (!nodeChildExists(node, i)) continue;
      const unsigned cx = x0 + ((i & 1) ? half : 0), cy = y0 + ((i & 2) ? half : 0), cz = z0 + ((i & 4) ? half : 0);
      if ((cx >> shift) >= lo && ((cx + half - 1) >> shift) <= hi) continue;  // wholly inside
      octomap::OcTreeNode* child = getNodeChild(node, i);
      if (!nodeHasChildren(child)) continue;  // a leaf: kept
      bool unlink = false;
      if (depth + 1 == window_depth) {
        std::vector<std::uint8_t> bytes;
        write_recurs(child, &bytes);
        out(cx >> shift, cy >> shift, cz >> shift, std::move(bytes));
        unlink = true;
      } else {
        const Dropped d = drop_recurs(child, depth + 1, cx, cy, cz, window_depth, lo, hi, out);
        if (d == kKept) continue;
        unlink = d == kEmptied;
      }
      changed = true;
      if (unlink) {
        tree_size -= count_recurs(child);
        deleteNodeRecurs(child);
        (node->*kChildren)[i] = nullptr;
      }
    }
    if (!changed) return kKept;
    if (!nodeHasChildren(node)) return kEmptied;
    node->updateOccupancyChildren();
    return kChanged;
  }
  std::size_t count_recurs(const octomap::OcTreeNode* node) const {
    std::size_t n = 1;
    for (unsigned i = 0; i < 8; ++i)
      if (nodeChildExists(node, i)) n += count_recurs(getNodeChild(node, i));
    return n;
  }
  // Pre-order: the node's log-odds (4 bytes), the mask of its children, then the children.
  void write_recurs(const octomap::OcTreeNode* node, std::vector<std::uint8_t>* bytes) const {
    const float v = node->getLogOdds();
    std::uint8_t mask = 0;
    for (unsigned i = 0; i < 8; ++i)
      if (nodeChildExists(node, i)) mask |= std::uint8_t(1u << i);
    const std::size_t at = bytes->size();
    bytes->resize(at + 5);
    std::memcpy(bytes->data() + at, &v, 4);
    (*bytes)[at + 4] = mask;
    for (unsigned i = 0; i < 8; ++i)
      if (mask & (1u << i)) write_recurs(getNodeChild(node, i), bytes);
  }
  void read_recurs(octomap::OcTreeNode* node, const std::vector<std::uint8_t>& bytes, std::size_t* at) {
    CANOPY_CHECK(*at + 5 <= bytes.size(), "collision environment: a moved-out subtree read past its end");
    float v = 0.f;
    std::memcpy(&v, bytes.data() + *at, 4);
    const std::uint8_t mask = bytes[*at + 4];
    *at += 5;
    node->setLogOdds(v);
    for (unsigned i = 0; i < 8; ++i)
      if (mask & (1u << i)) read_recurs(createNodeChild(node, i), bytes, at);
  }
};

// The window's unit: subtrees of 64 voxels a side (depth 10 of OctoMap's 16).
constexpr unsigned kWindowShift = 6;
constexpr unsigned kWindowDepth = 16 - kWindowShift;
inline std::uint64_t window_code(unsigned ix, unsigned iy, unsigned iz) {
  return std::uint64_t(ix) | (std::uint64_t(iy) << 10) | (std::uint64_t(iz) << 20);
}

}  // namespace env_tree

}  // namespace canopy::motion
