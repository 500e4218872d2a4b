#include "canopy/mapping/semantic_octree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>

#include "canopy/common/error.h"

namespace canopy::mapping {

SemanticOcTree::SemanticOcTree(const SemanticMapParams& params, const SemanticClasses& classes)
    : Base(params.resolution_m), params_(params), classes_(classes), rule_(params.rule()),
      unseen_entropy_(
          mapping::unseen_entropy(params.unseen_logodds, params.entropy_categories, static_cast<int>(classes.size()))) {
  CANOPY_CHECK(classes_.size() >= 1 && classes_.size() <= 255, "class count out of range");
}

namespace {
void copy_children(SemanticNode* d, const SemanticNode* s) {
  d->state() = s->state();
  for (unsigned i = 0; i < 8; ++i)
    if (const SemanticNode* c = s->child(i)) copy_children(d->make_child(i), c);
}
}  // namespace

SemanticOcTree::SemanticOcTree(const SemanticOcTree& other)
    : Base(other.params_.resolution_m), params_(other.params_), classes_(other.classes_), rule_(other.rule_),
      unseen_entropy_(other.unseen_entropy_), revision_(other.revision_) {
  if (other.root) {
    copy_children(create_root(), other.root);
    tree_size = other.tree_size;
    size_changed = true;
  }
}

SemanticOcTree::SemanticOcTree(SemanticOcTree&& other) noexcept
    : Base(other.params_.resolution_m), params_(other.params_), classes_(other.classes_), rule_(other.rule_),
      unseen_entropy_(other.unseen_entropy_), revision_(other.revision_) {
  swapContent(other);
  size_changed = true;
}

SemanticNode* SemanticOcTree::create_root() {
  CANOPY_CHECK(root == nullptr, "root exists already");
  root = new SemanticNode();
  ++tree_size;
  size_changed = true;
  return root;
}

const SemanticState* SemanticOcTree::find(const Vec3& p) const {
  octomap::OcTreeKey key;
  if (!key_of(p, &key)) return nullptr;
  return find(key);
}

double SemanticOcTree::occupancy(const Vec3& p) const {
  const SemanticState* s = find(p);
  return s ? s->occupancy() : 0.5;
}

double SemanticOcTree::entropy(const Vec3& p) const {
  const SemanticState* s = find(p);
  return s ? entropy_of(*s) : unseen_entropy_;
}

void SemanticOcTree::update_hit(const octomap::OcTreeKey& key, int c) {
  CANOPY_CHECK(c >= 0 && c < num_classes(), "class " << c << " out of range");
  apply_sorted_updates({VoxelUpdate{morton_code(key), static_cast<std::uint8_t>(c)}});
}

void SemanticOcTree::update_free(const octomap::OcTreeKey& key) {
  apply_sorted_updates({VoxelUpdate{morton_code(key), VoxelUpdate::kFree}});
}

bool SemanticNode::has_children() const {
  if (!children) return false;
  for (unsigned i = 0; i < 8; ++i)
    if (children[i]) return true;
  return false;
}

SemanticNode* SemanticNode::make_child(unsigned i) {
  if (!children) {
    children = new octomap::AbstractOcTreeNode*[8];
    for (unsigned k = 0; k < 8; ++k) children[k] = nullptr;
  }
  auto* n = new SemanticNode();
  children[i] = n;
  return n;
}

void SemanticNode::expand() {
  for (unsigned i = 0; i < 8; ++i) make_child(i)->value = value;
}

bool SemanticNode::collapse() {
  if (!children) return false;
  const SemanticNode* first = child(0);
  if (!first || first->has_children()) return false;
  for (unsigned i = 1; i < 8; ++i) {
    const SemanticNode* c = child(i);
    if (!c || c->has_children() || !(c->value == first->value)) return false;
  }
  value = first->value;
  for (unsigned i = 0; i < 8; ++i) delete static_cast<SemanticNode*>(children[i]);
  delete[] children;
  children = nullptr;
  return true;
}

namespace {
inline bool is_noop(const SemanticState& s, const VoxelUpdate& u, const UpdateRule& rule) {
  return u.label == VoxelUpdate::kFree ? s.free_is_noop(rule) : s.hit_is_noop(u.label, rule);
}
// A state left as it was: occupied before and after, or neither.
inline std::uint8_t unchanged_occupancy(const SemanticState& s) {
  return s.occupancy_logodds() > 0.f ? SemanticOcTree::kOccupiedBefore | SemanticOcTree::kOccupiedAfter : 0;
}
}  // namespace

void SemanticOcTree::apply_range(SemanticNode* top, unsigned top_depth, const VoxelUpdate* begin,
                                 const VoxelUpdate* end, bool collapse_top, bool top_is_fresh,
                                 UpdateCounts& counts, std::uint8_t* occupancy) {
  const bool prune = params_.prune;
  std::array<SemanticNode*, kOctreeDepth + 1> path{};
  path[top_depth] = top;
  unsigned reached = top_depth;  // deepest valid entry of `path` for the previous update
  // Nodes at depths (keep, reached] leave the path: collapse them bottom-up.
  const unsigned lowest = collapse_top ? top_depth : top_depth + 1;
  auto finish_path = [&](unsigned keep) {
    if (!prune) return;
    for (unsigned d = std::min(reached, kOctreeDepth - 1); d > keep && d >= lowest; --d)
      if (path[d]->collapse()) ++counts.pruned;
  };

  for (const VoxelUpdate* u = begin; u != end; ++u) {
    unsigned start = top_depth;
    if (u != begin) {
      CANOPY_CHECK(u->code > (u - 1)->code, "updates must be sorted by code without duplicates");
      const unsigned c = morton_common_depth((u - 1)->code, u->code);
      finish_path(c);
      start = std::max(top_depth, std::min(c, reached));
    }
    SemanticNode* node = path[start];
    unsigned d = start;
    bool skipped = false;
    // A node created empty is childless without being a pruned block.
    bool fresh = top_is_fresh && start == top_depth;
    for (; d < kOctreeDepth; ++d) {
      const unsigned idx = morton_child(u->code, d);
      SemanticNode* next = node->child(idx);
      const bool node_fresh = fresh;
      fresh = false;
      if (!next) {
        if (d > 0 && !node_fresh && !node->has_children()) {
          // A pruned block: leave it alone when the update cannot change it.
          if (is_noop(node->state(), *u, rule_)) {
            skipped = true;
            break;
          }
          node->expand();
          counts.created += 8;
          next = node->child(idx);
        } else {
          next = node->make_child(idx);
          ++counts.created;
          fresh = true;
        }
      }
      node = next;
      path[d + 1] = node;
    }
    reached = d;
    if (skipped || is_noop(node->state(), *u, rule_)) {
      if (occupancy) occupancy[u - begin] = unchanged_occupancy(node->state());
      ++counts.saturated;
      continue;
    }
    const bool before = node->state().occupancy_logodds() > 0.f;
    if (u->label == VoxelUpdate::kFree) {
      node->state().apply_free(rule_);
    } else {
      CANOPY_CHECK(u->label < num_classes(), "class " << int(u->label) << " out of range");
      node->state().apply_hit(u->label, rule_);
    }
    if (occupancy)
      occupancy[u - begin] = static_cast<std::uint8_t>((before ? kOccupiedBefore : 0) |
                                                       (node->state().occupancy_logodds() > 0.f ? kOccupiedAfter : 0));
    ++counts.applied;
  }
  finish_path(lowest == 0 ? 0 : lowest - 1);
}

UpdateCounts SemanticOcTree::apply_sorted_updates(const std::vector<VoxelUpdate>& updates,
                                                  std::vector<std::uint8_t>* occupancy) {
  UpdateCounts counts;
  if (occupancy) occupancy->assign(updates.size(), 0);
  if (updates.empty()) return counts;
  std::uint8_t* occ = occupancy ? occupancy->data() : nullptr;
  ++revision_;
  if (!root) create_root();  // counted in tree_size by create_root
  const std::size_t n = updates.size();
  const unsigned span_depth = morton_common_depth(updates.front().code, updates.back().code);
  const unsigned split = span_depth + 2;  // up to 64 disjoint subtrees
  const int threads = params_.threads > 0 ? params_.threads : tbb::this_task_arena::max_concurrency();
  if (n < 32768 || threads <= 1 || split >= kOctreeDepth) {  // small batches: waking workers costs more
    apply_range(root, 0, updates.data(), updates.data() + n, false, false, counts, occ);
  } else {
    // Groups of updates sharing their node at depth `split`; each group's subtree is edited by
    // one task. Nodes above `split` are created here, serially, in a fixed order.
    struct Group {
      std::size_t begin, end;
      SemanticNode* node;
      bool fresh;  // created here, so childless without being a pruned block
      std::array<SemanticNode*, kOctreeDepth + 1> path;
    };
    std::vector<Group> groups;
    const unsigned shift = 3 * (kOctreeDepth - split);
    for (std::size_t i = 0; i < n;) {
      std::size_t j = i + 1;
      while (j < n && (updates[j].code >> shift) == (updates[i].code >> shift)) ++j;
      Group g{i, j, nullptr, false, {}};
      SemanticNode* node = root;
      g.path[0] = root;
      unsigned d = 0;
      bool fresh = false;
      for (; d < split; ++d) {
        const unsigned idx = morton_child(updates[i].code, d);
        SemanticNode* next = node->child(idx);
        const bool node_fresh = fresh;
        fresh = false;
        if (!next) {
          if (d > 0 && !node_fresh && !node->has_children()) {
            bool all_noop = true;
            for (std::size_t k = i; k < j && all_noop; ++k) all_noop = is_noop(node->state(), updates[k], rule_);
            if (all_noop) break;
            node->expand();
            counts.created += 8;
            next = node->child(idx);
          } else {
            next = node->make_child(idx);
            ++counts.created;
            fresh = true;
            g.fresh = d + 1 == split;
          }
        }
        node = next;
        g.path[d + 1] = node;
      }
      if (d == split) {
        g.node = node;
        groups.push_back(g);
      } else {  // a pruned block none of the group's updates changes
        counts.saturated += j - i;
        if (occ) std::fill(occ + i, occ + j, unchanged_occupancy(node->state()));
      }
      i = j;
    }
    std::vector<UpdateCounts> group_counts(groups.size());
    auto run = [&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups.size(), 1), [&](const auto& r) {
        for (std::size_t g = r.begin(); g != r.end(); ++g)
          apply_range(groups[g].node, split, updates.data() + groups[g].begin, updates.data() + groups[g].end, true,
                      groups[g].fresh, group_counts[g], occ ? occ + groups[g].begin : nullptr);
      });
    };
    if (params_.threads > 0) {
      tbb::task_arena arena(params_.threads);
      arena.execute(run);
    } else {
      run();
    }
    for (const UpdateCounts& c : group_counts) {
      counts.applied += c.applied;
      counts.saturated += c.saturated;
      counts.created += c.created;
      counts.pruned += c.pruned;
    }
    // Collapse the nodes above `split` bottom-up, groups in order (deterministic).
    if (params_.prune) {
      for (unsigned d = split - 1; d >= 1; --d) {
        SemanticNode* last = nullptr;
        for (const Group& g : groups) {
          SemanticNode* node = g.path[d];
          if (node == last) continue;
          last = node;
          if (node->collapse()) ++counts.pruned;
        }
      }
    }
  }
  // Nodes created minus nodes removed by collapses.
  tree_size = tree_size + counts.created - 8 * counts.pruned;
  size_changed = true;
  return counts;
}

VoxelCounts SemanticOcTree::counts() const {
  VoxelCounts c;
  c.nodes = tree_size;
  c.memory_bytes = memoryUsage();
  const int target = classes_.target_index();
  for_each_leaf([&](const octomap::OcTreeKey&, unsigned depth, const SemanticState& s) {
    const std::size_t side = std::size_t(1) << (kOctreeDepth - depth);
    const std::size_t n = side * side * side;
    ++c.leaves;
    c.voxels += n;
    if (s.occupancy_logodds() > 0.f) {
      c.occupied += n;
      if (s.most_likely_class() == target) c.target += n;
    } else {
      c.free += n;
    }
  });
  return c;
}

namespace {
bool same_subtree(const SemanticOcTree& a, const SemanticNode* x, const SemanticOcTree& b, const SemanticNode* y) {
  if (!(x->state() == y->state()) && !a.nodeHasChildren(x)) return false;
  if (a.nodeHasChildren(x) != b.nodeHasChildren(y)) return false;
  for (unsigned i = 0; i < 8; ++i) {
    const bool ex = x->child(i) != nullptr, ey = y->child(i) != nullptr;
    if (ex != ey) return false;
    if (ex && !same_subtree(a, a.getNodeChild(x, i), b, b.getNodeChild(y, i))) return false;
  }
  return true;
}
}  // namespace

bool SemanticOcTree::identical(const SemanticOcTree& other) const {
  if (!(params_ == other.params_) || classes_.names != other.classes_.names || classes_.target != other.classes_.target)
    return false;
  if (tree_size != other.tree_size) return false;
  if ((root == nullptr) != (other.root == nullptr)) return false;
  return root == nullptr || same_subtree(*this, root, other, other.root);
}

}  // namespace canopy::mapping
