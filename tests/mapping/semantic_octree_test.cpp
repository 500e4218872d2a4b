#include <gtest/gtest.h>

#include <algorithm>
#include <random>

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
