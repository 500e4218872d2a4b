#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mapping/semantic_octree.h"

using namespace canopy;
using namespace canopy::mapping;

namespace {
SemanticOcTree make_tree(int threads = 1, bool prune = true) {
  SemanticMapParams p;
  p.threads = threads;
  p.prune = prune;
  return SemanticOcTree(p, SemanticClasses{});
}
constexpr int kFruitId = 2;
}  // namespace

TEST(SemanticOcTree, NodeIsCompact) {
  EXPECT_LE(sizeof(SemanticNode), 32u);
}

TEST(SemanticOcTree, MortonRoundTripAndChildOrder) {
  std::mt19937 rng(3);
  for (int i = 0; i < 1000; ++i) {
    const octomap::OcTreeKey k(rng() & 0xffff, rng() & 0xffff, rng() & 0xffff);
    EXPECT_EQ(morton_key(morton_code(k)), k);
    for (int depth = 0; depth < 16; ++depth)
      EXPECT_EQ((morton_code(k) >> (3 * depth)) & 7, octomap::computeChildIdx(k, depth));
  }
}

TEST(SemanticOcTree, UnknownUntilObserved) {
  SemanticOcTree map = make_tree();
  const Vec3 p(0.1, 0.2, 0.3);
  EXPECT_TRUE(map.is_unknown(p));
  EXPECT_DOUBLE_EQ(map.occupancy(p), 0.5);
  EXPECT_DOUBLE_EQ(map.entropy(p), map.unseen_entropy());
  octomap::OcTreeKey k;
  ASSERT_TRUE(map.key_of(p, &k));
  map.update_hit(k, kFruitId);
  ASSERT_FALSE(map.is_unknown(p));
  EXPECT_EQ(map.find(p)->most_likely_class(), kFruitId);
  EXPECT_EQ(map.find(p)->logodds[0], 1.0f);
  // Neighbours stay unknown.
  EXPECT_TRUE(map.is_unknown(p + Vec3(0.015, 0, 0)));
  EXPECT_EQ(map.size(), 17u);  // root + 16 levels
}

TEST(SemanticOcTree, PruningKeepsSemantics) {
  SemanticOcTree map = make_tree();
  // Eight siblings get the same hit: they collapse into their parent.
  const octomap::OcTreeKey base(32768, 32768, 32768);
  std::vector<VoxelUpdate> batch;
  for (int i = 0; i < 8; ++i)
    batch.push_back({morton_code(octomap::OcTreeKey(base[0] + (i & 1), base[1] + ((i >> 1) & 1), base[2] + (i >> 2))),
                     static_cast<std::uint8_t>(kFruitId)});
  std::sort(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code < b.code; });
  const auto counts = map.apply_sorted_updates(batch);
  EXPECT_GE(counts.pruned, 1u);
  EXPECT_EQ(map.size(), 16u);  // the 8 leaves became one
  for (const auto& u : batch) {
    const SemanticState* s = map.find(morton_key(u.code));
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->most_likely_class(), kFruitId);
    EXPECT_EQ(s->logodds[0], 1.0f);
  }
  // A different update to one voxel expands the block; the others keep their state.
  map.update_free(morton_key(batch[3].code));
  EXPECT_EQ(map.size(), 24u);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const SemanticState* s = map.find(morton_key(batch[i].code));
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->logodds[0], i == 3 ? 0.9f : 1.0f);
  }
  // Eight siblings with different states never collapse.
  SemanticOcTree map2 = make_tree();
  for (int i = 0; i < 8; ++i)
    map2.update_hit(morton_key(batch[static_cast<std::size_t>(i)].code), i % 2 ? kFruitId : 1);
  EXPECT_EQ(map2.size(), 24u);
}

TEST(SemanticOcTree, SaturatedPrunedBlockIsNotExpanded) {
  SemanticOcTree map = make_tree();
  const octomap::OcTreeKey base(40000, 40000, 40000);
  std::vector<VoxelUpdate> batch;
  for (int i = 0; i < 8; ++i)
    batch.push_back({morton_code(octomap::OcTreeKey(base[0] + (i & 1), base[1] + ((i >> 1) & 1), base[2] + (i >> 2))),
                     VoxelUpdate::kFree});
  std::sort(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code < b.code; });
  for (int rep = 0; rep < 100; ++rep) map.apply_sorted_updates(batch);
  const std::size_t size = map.size();
  const auto counts = map.apply_sorted_updates({batch[0]});
  EXPECT_EQ(counts.saturated, 1u);
  EXPECT_EQ(counts.created, 0u);
  EXPECT_EQ(map.size(), size);
  EXPECT_EQ(map.find(morton_key(batch[5].code))->others, -9.21f);
}

// A batch applied at once equals the same updates applied one by one, with 1 or 2 threads.
TEST(SemanticOcTree, BatchEqualsSingleUpdatesAndIsThreadIndependent) {
  std::mt19937 rng(7);
  std::vector<std::vector<VoxelUpdate>> scans;
  for (int s = 0; s < 4; ++s) {
    std::vector<VoxelUpdate> batch;
    for (int i = 0; i < 60000; ++i) {
      const octomap::OcTreeKey k(32700 + rng() % 60, 32700 + rng() % 60, 32760 + rng() % 30);
      const std::uint8_t label = rng() % 4 == 0 ? VoxelUpdate::kFree : static_cast<std::uint8_t>(rng() % 3);
      batch.push_back({morton_code(k), label});
    }
    std::sort(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code < b.code; });
    batch.erase(std::unique(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code == b.code; }),
                batch.end());
    scans.push_back(batch);
  }
  SemanticOcTree serial = make_tree(1), parallel = make_tree(2), single = make_tree(1);
  for (const auto& batch : scans) {
    serial.apply_sorted_updates(batch);
    parallel.apply_sorted_updates(batch);
    for (const auto& u : batch) {
      if (u.label == VoxelUpdate::kFree) single.update_free(morton_key(u.code));
      else single.update_hit(morton_key(u.code), u.label);
    }
  }
  EXPECT_EQ(serial.size(), parallel.size());
  EXPECT_EQ(serial.size(), single.size());
  std::size_t checked = 0;
  serial.for_each_leaf([&](const octomap::OcTreeKey& key, unsigned depth, const SemanticState& s) {
    if (depth != 16) return;
    const SemanticState* a = parallel.find(key);
    const SemanticState* b = single.find(key);
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(*a, s);
    EXPECT_EQ(*b, s);
    ++checked;
  });
  EXPECT_GT(checked, 1000u);
  // Unpruned trees hold every voxel as its own leaf.
  SemanticOcTree unpruned = make_tree(2, false);
  for (const auto& batch : scans) unpruned.apply_sorted_updates(batch);
  EXPECT_GE(unpruned.size(), serial.size());
}

TEST(SemanticOcTree, CopyIsDeepAndIdentical) {
  SemanticOcTree map = make_tree();
  map.update_hit(octomap::OcTreeKey(32768, 32768, 32768), kFruitId);
  map.update_free(octomap::OcTreeKey(32769, 32768, 32768));
  SemanticOcTree copy(map);
  EXPECT_TRUE(copy.identical(map));
  copy.update_free(octomap::OcTreeKey(32768, 32768, 32768));
  EXPECT_FALSE(copy.identical(map));
  const VoxelCounts c = map.counts();
  EXPECT_EQ(c.voxels, 2u);
  EXPECT_EQ(c.occupied, 1u);
  EXPECT_EQ(c.target, 1u);
  EXPECT_EQ(c.free, 1u);
}

// The walk of a key box visits the voxels of the whole walk that lie in the box, in the same
// order (pruned blocks overlapping the box are expanded whole, like the whole walk does).
TEST(SemanticOcTree, KeyBoxWalkIsTheWholeWalkFiltered) {
  SemanticOcTree map(SemanticMapParams{}, SemanticClasses{});
  // A solid block of identical hits (collapsed into pruned blocks) with other-class voxels in it.
  std::vector<VoxelUpdate> u;
  for (int x = 0; x < 16; ++x)
    for (int y = 0; y < 16; ++y)
      for (int z = 0; z < 4; ++z) {
        const octomap::OcTreeKey k(static_cast<octomap::key_type>(32768 + x), static_cast<octomap::key_type>(32768 + y),
                                   static_cast<octomap::key_type>(32768 + z));
        u.push_back({morton_code(k), std::uint8_t((x * 7 + y * 3 + z) % 11 == 0 ? 1 : 2)});
      }
  std::sort(u.begin(), u.end(), [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.code < b.code; });
  map.apply_sorted_updates(u);
  map.apply_sorted_updates(u);
  std::size_t blocks = 0;
  map.for_each_leaf([&](const octomap::OcTreeKey&, unsigned depth, const SemanticState&) { blocks += depth < 16; });
  EXPECT_GT(blocks, 0u);
  const octomap::OcTreeKey lo(32770, 32765, 32769), hi(32775, 32772, 32771);
  auto inside = [&](const octomap::OcTreeKey& k) {
    for (int a = 0; a < 3; ++a)
      if (k[a] < lo[a] || k[a] > hi[a]) return false;
    return true;
  };
  const auto keep = [](const SemanticState& s) { return s.most_likely_class() == 2; };
  std::vector<std::uint64_t> whole, boxed;
  map.for_each_voxel_if(keep, [&](const octomap::OcTreeKey& k, const SemanticState&) {
    if (inside(k)) whole.push_back(morton_code(k));
  });
  map.for_each_voxel_in_keys_if(lo, hi, keep, [&](const octomap::OcTreeKey& k, const SemanticState&) {
    if (inside(k)) boxed.push_back(morton_code(k));
  });
  EXPECT_GT(whole.size(), 20u);
  EXPECT_EQ(boxed, whole);
}

// The occupancy bytes apply_sorted_updates reports equal lookups of each voxel before and
// after the batch, on the serial and the split (parallel) path, with pruned blocks.
TEST(SemanticOcTree, ReportedOccupancyEqualsLookupsBeforeAndAfter) {
  std::mt19937 rng(11);
  auto occupied = [](const SemanticOcTree& m, std::uint64_t code) {
    const SemanticState* s = m.find(morton_key(code));
    return s && s->occupancy_logodds() > 0.f;
  };
  for (const int threads : {1, 2}) {
    SemanticOcTree map = make_tree(threads);
    std::size_t flips = 0, both = 0;
    for (int s = 0; s < 12; ++s) {
      const int n = s % 2 ? 60000 : 5000;  // above and below the split path's threshold
      const bool mostly_free = s % 3 == 2;
      std::vector<VoxelUpdate> batch;
      for (int i = 0; i < n; ++i) {
        const octomap::OcTreeKey k(32700 + rng() % 40, 32700 + rng() % 40, 32760 + rng() % 24);
        const bool free = mostly_free ? rng() % 8 != 0 : rng() % 3 == 0;
        batch.push_back({morton_code(k), free ? VoxelUpdate::kFree : static_cast<std::uint8_t>(rng() % 3)});
      }
      std::sort(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code < b.code; });
      batch.erase(std::unique(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code == b.code; }),
                  batch.end());
      std::vector<std::uint8_t> expected(batch.size());
      for (std::size_t i = 0; i < batch.size(); ++i)
        expected[i] = occupied(map, batch[i].code) ? SemanticOcTree::kOccupiedBefore : 0;
      std::vector<std::uint8_t> reported;
      map.apply_sorted_updates(batch, &reported);
      ASSERT_EQ(reported.size(), batch.size());
      for (std::size_t i = 0; i < batch.size(); ++i) {
        if (occupied(map, batch[i].code)) expected[i] |= SemanticOcTree::kOccupiedAfter;
        ASSERT_EQ(int(reported[i]), int(expected[i])) << "threads " << threads << ", batch " << s << ", update " << i;
        flips += expected[i] == SemanticOcTree::kOccupiedBefore || expected[i] == SemanticOcTree::kOccupiedAfter;
        both += expected[i] == (SemanticOcTree::kOccupiedBefore | SemanticOcTree::kOccupiedAfter);
      }
    }
    EXPECT_GT(flips, 1000u);  // the scenes exercise both changes and unchanged voxels
    EXPECT_GT(both, 1000u);
  }
}

// Issue 49: keep_x() moves the subtrees wholly outside a stretch of x out as compact bytes.
// Against a map that took the same scans whole: every count, every update's counters, every read
// and box walk inside the stretch equal; a read inside a moved-out subtree (find, the whole walk,
// the root) is an internal error; after keep_all() (or on a copy) the map is the whole one node
// for node, in the map file's bytes too.
TEST(SemanticOcTree, AMapWithItsFarPartMovedOutIsTheWholeMap) {
  const double res = SemanticMapParams{}.resolution_m;
  auto key_x = [&](double x) { return static_cast<unsigned>(std::floor(x / res) + 32768.0); };
  std::mt19937 rng(11);
  // A scan near x_m: free voxels and hits of three classes within +-2 m, and a solid block of
  // one class's hits (saturating into pruned blocks over the scans).
  auto scan = [&](double x_m) {
    std::vector<VoxelUpdate> batch;
    const unsigned cx = key_x(x_m);
    for (int i = 0; i < 12000; ++i) {
      const octomap::OcTreeKey k(static_cast<octomap::key_type>(cx - 133 + rng() % 267),
                                 static_cast<octomap::key_type>(32700 + rng() % 100),
                                 static_cast<octomap::key_type>(32760 + rng() % 40));
      const std::uint8_t label = rng() % 3 == 0 ? VoxelUpdate::kFree : static_cast<std::uint8_t>(rng() % 3);
      batch.push_back({morton_code(k), label});
    }
    const unsigned bx = (cx & ~15u);
    for (unsigned z = 0; z < 16; ++z)
      for (unsigned y = 0; y < 16; ++y)
        for (unsigned x = 0; x < 16; ++x)
          batch.push_back({morton_code(octomap::OcTreeKey(static_cast<octomap::key_type>(bx + x),
                                                          static_cast<octomap::key_type>(32816 + y),
                                                          static_cast<octomap::key_type>(32768 + z))),
                           static_cast<std::uint8_t>(kFruitId)});
    std::sort(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code < b.code; });
    batch.erase(std::unique(batch.begin(), batch.end(), [](auto& a, auto& b) { return a.code == b.code; }),
                batch.end());
    return batch;
  };
  auto same_counts = [](const VoxelCounts& a, const VoxelCounts& b) {
    EXPECT_EQ(a.leaves, b.leaves);
    EXPECT_EQ(a.voxels, b.voxels);
    EXPECT_EQ(a.occupied, b.occupied);
    EXPECT_EQ(a.free, b.free);
    EXPECT_EQ(a.target, b.target);
    EXPECT_EQ(a.nodes, b.nodes);
  };
  SemanticOcTree whole = make_tree(2), held = make_tree(2);
  std::vector<double> stops;
  for (double x = 0.0; x <= 20.0; x += 1.0) stops.push_back(x);
  for (double x = 18.0; x >= 0.0; x -= 3.0) stops.push_back(x);  // back over what was moved out
  std::size_t most_moved = 0, thrown = 0, smaller = 0, walked_all = 0;
  for (std::size_t s = 0; s < stops.size(); ++s) {
    const double c = stops[s];
    held.keep_x(c - 3.0, c + 3.0);
    most_moved = std::max(most_moved, held.moved_out());
    same_counts(held.counts(), whole.counts());
    smaller += held.memory_bytes() < whole.memory_bytes();
    const unsigned lo = key_x(c - 3.0) >> 6, hi = key_x(c + 3.0) >> 6;
    // Reads inside the stretch: the whole map's.
    for (int i = 0; i < 3000; ++i) {
      const octomap::OcTreeKey k(static_cast<octomap::key_type>((lo << 6) + rng() % ((hi - lo + 1) << 6)),
                                 static_cast<octomap::key_type>(32690 + rng() % 140),
                                 static_cast<octomap::key_type>(32750 + rng() % 40));
      const SemanticState* a = held.find(k);
      const SemanticState* b = whole.find(k);
      ASSERT_EQ(a == nullptr, b == nullptr);
      if (a) {
        EXPECT_EQ(*a, *b);
      }
    }
    // A box walk inside the stretch: the whole map's, voxel for voxel.
    const octomap::OcTreeKey box_lo(static_cast<octomap::key_type>(lo << 6), 32690, 32750),
        box_hi(static_cast<octomap::key_type>(((hi + 1) << 6) - 1), 32840, 32790);
    std::vector<std::pair<std::uint64_t, std::uint8_t>> wa, wb;
    auto all = [](const SemanticState&) { return true; };
    held.for_each_voxel_in_keys_if(box_lo, box_hi, all, [&](const octomap::OcTreeKey& k, const SemanticState& st) {
      wa.emplace_back(morton_code(k), st.count);
    });
    whole.for_each_voxel_in_keys_if(box_lo, box_hi, all, [&](const octomap::OcTreeKey& k, const SemanticState& st) {
      wb.emplace_back(morton_code(k), st.count);
    });
    EXPECT_EQ(wa, wb);
    // Reads inside a moved-out subtree: internal errors, never "unknown".
    if (held.moved_out() > 0) {
      EXPECT_THROW(held.getRoot(), InternalError);
      EXPECT_THROW(held.for_each_leaf([](const octomap::OcTreeKey&, unsigned, const SemanticState&) {}), InternalError);
      int tried = 0;
      whole.for_each_leaf([&](const octomap::OcTreeKey& k, unsigned depth, const SemanticState&) {
        if (depth != 16 || tried >= 20) return;
        const unsigned w = unsigned(k[0]) >> 6;
        if (w >= lo && w <= hi) return;
        ++tried;
        EXPECT_THROW(held.find(k), InternalError);
      });
      thrown += tried;
    }
    // The walk that decodes the moved-out subtrees: the whole map's, leaf for leaf (at two stops).
    if (held.moved_out() > 0 && s % 13 == 12) {
      std::vector<std::tuple<std::uint64_t, unsigned, SemanticState>> la, lb;
      held.for_each_leaf_all([&](const octomap::OcTreeKey& k, unsigned depth, const SemanticState& st) {
        la.emplace_back(morton_code(k), depth, st);
      });
      whole.for_each_leaf([&](const octomap::OcTreeKey& k, unsigned depth, const SemanticState& st) {
        lb.emplace_back(morton_code(k), depth, st);
      });
      ASSERT_EQ(la.size(), lb.size());
      for (std::size_t i = 0; i < la.size(); ++i) {
        ASSERT_EQ(std::get<0>(la[i]), std::get<0>(lb[i])) << i;
        ASSERT_EQ(std::get<1>(la[i]), std::get<1>(lb[i])) << i;
        ASSERT_EQ(std::get<2>(la[i]), std::get<2>(lb[i])) << i;
      }
      walked_all += la.size();
      EXPECT_GT(held.moved_out(), 0u);  // still moved out: the walk changed nothing
    }
    // The scan: here, and now and then far behind (its subtrees come back first).
    std::vector<VoxelUpdate> batch = scan(c);
    UpdateCounts ua = held.apply_sorted_updates(batch), ub = whole.apply_sorted_updates(batch);
    EXPECT_EQ(ua.applied, ub.applied);
    EXPECT_EQ(ua.saturated, ub.saturated);
    EXPECT_EQ(ua.created, ub.created);
    EXPECT_EQ(ua.pruned, ub.pruned);
    if (s % 4 == 3) {
      batch = scan(c - 8.0);
      ua = held.apply_sorted_updates(batch);
      ub = whole.apply_sorted_updates(batch);
      EXPECT_EQ(ua.applied, ub.applied);
      EXPECT_EQ(ua.created, ub.created);
      EXPECT_EQ(ua.pruned, ub.pruned);
    }
    same_counts(held.counts(), whole.counts());
    EXPECT_EQ(held.revision(), whole.revision());
  }
  EXPECT_GT(most_moved, 10u);
  EXPECT_GT(thrown, 100u);
  EXPECT_GT(walked_all, 10000u);
  EXPECT_GT(smaller, stops.size() / 2);
  // A copy of the held map, put back whole, and the held map itself: the whole map.
  SemanticOcTree copy(held);
  EXPECT_GT(copy.moved_out(), 0u);
  copy.keep_all();
  EXPECT_TRUE(copy.identical(whole));
  held.keep_all();
  EXPECT_EQ(held.moved_out(), 0u);
  EXPECT_TRUE(held.identical(whole));
  EXPECT_EQ(serialize_map(held), serialize_map(whole));
  const VoxelCounts a = held.counts(), b = whole.counts();
  same_counts(a, b);
  EXPECT_EQ(a.memory_bytes, b.memory_bytes);
}
