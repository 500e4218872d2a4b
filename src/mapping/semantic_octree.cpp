#include "canopy/mapping/semantic_octree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "canopy/common/error.h"
#include "canopy/common/zstd_bytes.h"

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
      unseen_entropy_(other.unseen_entropy_), revision_(other.revision_), windowed_(other.windowed_),
      window_lo_(other.window_lo_), window_hi_(other.window_hi_), moved_(other.moved_), moved_bytes_(other.moved_bytes_) {
  if (other.root) {
    copy_children(create_root(), other.root);
    tree_size = other.tree_size;
    size_changed = true;
  }
}

SemanticOcTree::SemanticOcTree(SemanticOcTree&& other) noexcept
    : Base(other.params_.resolution_m), params_(other.params_), classes_(other.classes_), rule_(other.rule_),
      unseen_entropy_(other.unseen_entropy_), revision_(other.revision_), windowed_(other.windowed_),
      window_lo_(other.window_lo_), window_hi_(other.window_hi_), moved_(std::move(other.moved_)),
      moved_bytes_(other.moved_bytes_) {
  swapContent(other);
  size_changed = true;
  other.moved_.clear();
  other.moved_bytes_ = 0;
  other.windowed_ = false;
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
  put_back_updated(updates);  // a change where a subtree was moved out (keep_x): it comes back first
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

namespace {
// A leaf at `depth` with state `s` added to `c` (its voxels: the block it stands for).
void count_leaf(const SemanticState& s, unsigned depth, int target, VoxelCounts* c) {
  const std::size_t side = std::size_t(1) << (kOctreeDepth - depth);
  const std::size_t n = side * side * side;
  ++c->leaves;
  c->voxels += n;
  if (s.occupancy_logodds() > 0.f) {
    c->occupied += n;
    if (s.most_likely_class() == target) c->target += n;
  } else {
    c->free += n;
  }
}

// Counts of the leaves under `node` at `depth`; stubs (moved out) are skipped.
void count_leaves(const SemanticNode* node, unsigned depth, int target, std::uint8_t stub, VoxelCounts* c) {
  if (!node->has_children()) {
    if (node->state().count != stub) count_leaf(node->state(), depth, target, c);
    return;
  }
  for (unsigned i = 0; i < 8; ++i)
    if (const SemanticNode* ch = node->child(i)) count_leaves(ch, depth + 1, target, stub, c);
}
}  // namespace

VoxelCounts SemanticOcTree::counts() const {
  VoxelCounts c;
  c.nodes = tree_size;
  c.memory_bytes = memory_bytes();
  if (root) count_leaves(root, 0, classes_.target_index(), kMovedOutMark, &c);
  for (const auto& [code, m] : moved_) {
    c.nodes += m.counts.nodes - 1;  // its stub is in tree_size
    c.leaves += m.counts.leaves;
    c.voxels += m.counts.voxels;
    c.occupied += m.counts.occupied;
    c.free += m.counts.free;
    c.target += m.counts.target;
  }
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
  if (!moved_.empty() || !other.moved_.empty()) moved_out_walk();
  if (!(params_ == other.params_) || classes_.names != other.classes_.names || classes_.target != other.classes_.target)
    return false;
  if (tree_size != other.tree_size) return false;
  if ((root == nullptr) != (other.root == nullptr)) return false;
  return root == nullptr || same_subtree(*this, root, other, other.root);
}


// --- The far part kept compactly (keep_x, issue 49) ---------------------------------------

void SemanticNode::delete_children() {
  if (!children) return;
  for (unsigned i = 0; i < 8; ++i) {
    if (auto* c = static_cast<SemanticNode*>(children[i])) {
      c->delete_children();
      delete c;
    }
  }
  delete[] children;
  children = nullptr;
}

void SemanticOcTree::moved_out_read(const octomap::OcTreeKey& key) const {
  CANOPY_CHECK(false, "semantic map: voxel key (" << key[0] << ", " << key[1] << ", " << key[2] << "), x = "
                                                  << keyToCoord(key[0]) << " m, is in a subtree moved out (keep_x)");
  std::abort();  // not reached
}

std::string SemanticOcTree::moved_out_bytes(std::uint64_t code) const {
  const auto it = moved_.find(code);
  CANOPY_CHECK(it != moved_.end(), "semantic map: a stub without its moved-out subtree at window code " << code);
  return zstd_decompress(it->second.bytes, "a moved-out map subtree");
}

void SemanticOcTree::moved_out_walk() const {
  CANOPY_CHECK(false, "semantic map: a walk over the whole tree while " << moved_.size()
                                                                        << " subtrees are moved out (keep_x)");
  std::abort();  // not reached
}

namespace {
constexpr unsigned kMovedShift = 3 * (kOctreeDepth - SemanticOcTree::kMovedDepth);  // window code = morton >> this
static_assert(sizeof(SemanticState) == 20, "a moved-out node's state is its 20 bytes");

// Pre-order: the node's state (20 bytes as held), the mask of its children, then the children.
void write_moved(const SemanticNode* node, unsigned depth, const int target, std::string* bytes, VoxelCounts* c) {
  std::uint8_t mask = 0;
  for (unsigned i = 0; i < 8; ++i)
    if (node->child(i)) mask |= std::uint8_t(1u << i);
  const std::size_t at = bytes->size();
  bytes->resize(at + sizeof(SemanticState) + 1);
  std::memcpy(bytes->data() + at, &node->state(), sizeof(SemanticState));
  (*bytes)[at + sizeof(SemanticState)] = static_cast<char>(mask);
  ++c->nodes;
  if (mask == 0) {
    count_leaf(node->state(), depth, target, c);
    return;
  }
  for (unsigned i = 0; i < 8; ++i)
    if (mask & (1u << i)) write_moved(node->child(i), depth + 1, target, bytes, c);
}

std::size_t read_moved(SemanticNode* node, const std::string& bytes, std::size_t* at) {
  CANOPY_CHECK(*at + sizeof(SemanticState) + 1 <= bytes.size(), "semantic map: a moved-out subtree read past its end");
  std::memcpy(&node->state(), bytes.data() + *at, sizeof(SemanticState));
  const auto mask = static_cast<std::uint8_t>(bytes[*at + sizeof(SemanticState)]);
  *at += sizeof(SemanticState) + 1;
  std::size_t nodes = 1;
  for (unsigned i = 0; i < 8; ++i)
    if (mask & (1u << i)) nodes += read_moved(node->make_child(i), bytes, at);
  return nodes;
}
}  // namespace

SemanticNode* SemanticOcTree::window_node(std::uint64_t code) const {
  SemanticNode* node = root;
  for (unsigned d = 0; node && d < kMovedDepth; ++d)
    node = node->child(static_cast<unsigned>(code >> (3 * (kMovedDepth - 1 - d))) & 7u);
  return node;
}

void SemanticOcTree::move_out(SemanticNode* node, std::uint64_t code) {
  MovedOut m;
  std::string raw;
  write_moved(node, kMovedDepth, classes_.target_index(), &raw, &m.counts);
  m.bytes = zstd_compress(raw, 1);
  m.bytes.shrink_to_fit();
  node->delete_children();
  node->state() = SemanticState{};
  node->state().count = kMovedOutMark;
  tree_size -= m.counts.nodes - 1;  // the stub stays
  size_changed = true;
  moved_bytes_ += m.bytes.size();
  moved_.emplace(code, std::move(m));
}

void SemanticOcTree::put_back(std::uint64_t code) {
  const auto it = moved_.find(code);
  CANOPY_CHECK(it != moved_.end(), "semantic map: no subtree moved out at window code " << code);
  SemanticNode* node = window_node(code);
  CANOPY_CHECK(node && !node->has_children() && node->state().count == kMovedOutMark,
               "semantic map: the stub of a moved-out subtree is gone");
  const std::string raw = zstd_decompress(it->second.bytes, "a moved-out map subtree");
  std::size_t at = 0;
  const std::size_t nodes = read_moved(node, raw, &at);
  CANOPY_CHECK(at == raw.size() && nodes == it->second.counts.nodes, "semantic map: a moved-out subtree read short");
  tree_size += nodes - 1;
  size_changed = true;
  moved_bytes_ -= it->second.bytes.size();
  moved_.erase(it);
}

void SemanticOcTree::move_out_recurs(SemanticNode* node, unsigned depth, std::uint64_t code, unsigned lo, unsigned hi) {
  // `node` at `depth` covers window x [ix << s, ((ix + 1) << s) - 1], s = kMovedDepth - depth.
  const unsigned s = kMovedDepth - depth;
  const unsigned ix = detail::compact3(code);
  const unsigned first = ix << s, last = ((ix + 1) << s) - 1;
  if (first >= lo && last <= hi) return;  // wholly inside
  if (!node->has_children()) return;      // a leaf (or a stub): kept
  if (depth == kMovedDepth) {
    move_out(node, code);
    return;
  }
  for (unsigned i = 0; i < 8; ++i)
    if (SemanticNode* c = node->child(i)) move_out_recurs(c, depth + 1, (code << 3) | i, lo, hi);
}

void SemanticOcTree::keep_x(double x_lo_m, double x_hi_m) {
  CANOPY_CHECK(std::isfinite(x_lo_m) && std::isfinite(x_hi_m) && x_lo_m <= x_hi_m,
               "SemanticOcTree::keep_x: [" << x_lo_m << ", " << x_hi_m << "] is not a stretch");
  const double res = getResolution();
  auto window_x = [&](double x) {
    const double k = std::clamp(std::floor(x / res) + double(tree_max_val), 0.0, 65535.0);
    return unsigned(k) >> (kOctreeDepth - kMovedDepth);
  };
  const unsigned lo = window_x(x_lo_m), hi = window_x(x_hi_m);
  windowed_ = true;
  window_lo_ = lo;
  window_hi_ = hi;
  std::vector<std::uint64_t> back;
  for (const auto& [code, m] : moved_) {
    const unsigned ix = detail::compact3(code);
    if (ix >= lo && ix <= hi) back.push_back(code);
  }
  std::sort(back.begin(), back.end());
  for (const std::uint64_t code : back) put_back(code);
  if (root) move_out_recurs(root, 0, 0, lo, hi);
}

void SemanticOcTree::keep_all() {
  std::vector<std::uint64_t> back;
  for (const auto& [code, m] : moved_) back.push_back(code);
  std::sort(back.begin(), back.end());
  for (const std::uint64_t code : back) put_back(code);
  windowed_ = false;
}

void SemanticOcTree::put_back_updated(const std::vector<VoxelUpdate>& updates) {
  if (moved_.empty()) return;
  std::uint64_t last = ~std::uint64_t(0);
  for (const VoxelUpdate& u : updates) {
    const std::uint64_t code = u.code >> kMovedShift;
    if (code == last) continue;
    last = code;
    if (moved_.count(code)) put_back(code);
  }
}

std::size_t SemanticOcTree::memory_bytes() const {
  return memoryUsage() + moved_bytes_ + moved_.size() * (sizeof(MovedOut) + 32);
}

}  // namespace canopy::mapping
