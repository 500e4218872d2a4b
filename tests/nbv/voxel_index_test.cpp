#include <gtest/gtest.h>

#include "canopy/common/random.h"
#include "canopy/nbv/voxel_index.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

void expect_same_info(const VoxelInfo& a, const VoxelInfo& b) {
  EXPECT_EQ(a.known, b.known);
  EXPECT_EQ(a.is_target, b.is_target);
  EXPECT_EQ(a.cls, b.cls);
  EXPECT_EQ(a.p_occ, b.p_occ);
  EXPECT_EQ(a.entropy, b.entropy);
  EXPECT_EQ(a.binary_entropy, b.binary_entropy);
  EXPECT_EQ(a.kl_free, b.kl_free);
  for (int k = 0; k < VoxelInfo::kMaxCategories; ++k) {
    EXPECT_EQ(a.prob[k], b.prob[k]);
    EXPECT_EQ(a.kl_hit[k], b.kl_hit[k]);
  }
}

}  // namespace

// Every voxel of the tree (pruned blocks expanded) has the index entry of its own state, and
// unknown voxels give id 0.
TEST(VoxelIndex, LookupMatchesTheTree) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map();
  VoxelIndex index(map);
  std::size_t checked = 0, blocks = 0;
  map.for_each_leaf([&](const octomap::OcTreeKey& key, unsigned depth, const mapping::SemanticState& s) {
    const int side = 1 << (16 - depth), half = side / 2;
    if (side > 1) ++blocks;
    const VoxelInfo expected = make_voxel_info(map, &s);
    // corners of the block (enough to catch fill errors) and its key voxel
    for (int c = 0; c < 8; ++c) {
      const octomap::OcTreeKey k(static_cast<octomap::key_type>(key[0] - half + ((c & 1) ? side - 1 : 0)),
                                 static_cast<octomap::key_type>(key[1] - half + ((c & 2) ? side - 1 : 0)),
                                 static_cast<octomap::key_type>(key[2] - half + ((c & 4) ? side - 1 : 0)));
      const std::uint32_t id = index.lookup(k);
      ASSERT_NE(id, 0u);
      expect_same_info(index.info(id), expected);
      ++checked;
    }
  });
  EXPECT_GT(checked, 10000u);
  EXPECT_GT(blocks, 10u);  // the scene has pruned free blocks
  octomap::OcTreeKey far;
  ASSERT_TRUE(map.key_of(Vec3(5.0, 5.0, 5.0), &far));
  EXPECT_EQ(index.lookup(far), 0u);
  EXPECT_FALSE(index.unknown().known);
  EXPECT_DOUBLE_EQ(index.unknown().entropy, float(map.unseen_entropy()));
}

// The fast traversal visits exactly the voxels of computeRayKeys + search, with the same values.
TEST(VoxelIndex, FastTraversalEqualsReference) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map();
  VoxelIndex index(map);
  Rng rng(7);
  std::vector<RayVoxel> fast(4096);
  std::vector<octomap::OcTreeKey> keys(4096);
  std::vector<ReferenceVoxel> ref;
  octomap::KeyRay scratch;
  std::size_t voxels = 0, known = 0;
  for (int r = 0; r < 3000; ++r) {
    const Vec3 o = Vec3(0.5, 0.15, 1.0) + Vec3(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), rng.uniform(-0.4, 0.4));
    Vec3 e = Vec3(0.5, 0.15, 1.0) + Vec3(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
    if (r % 10 == 0) e = o + Vec3(rng.uniform(-0.5, 0.5), 0.0, 0.0);  // axis-aligned rays
    const Vec3 target(0.5, 0.0, 1.0);
    const std::size_t n = index.cast(o, e, target, fast.data(), fast.size(), nullptr, keys.data());
    ref.clear();
    ASSERT_TRUE(cast_reference(map, o, e, &scratch, &ref));
    ASSERT_EQ(n, ref.size()) << "ray " << r;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(keys[i], ref[i].key) << "ray " << r << " voxel " << i;
      expect_same_info(*fast[i].info, make_voxel_info(map, ref[i].state));
      EXPECT_EQ(fast[i].dist2_m2, float((map.center_of(ref[i].key) - target).squaredNorm()));
      known += ref[i].state != nullptr;
    }
    voxels += n;
  }
  EXPECT_GT(voxels, 50000u);
  EXPECT_GT(known, 5000u);  // rays through observed space too, not only unknown
}

// Reversing a ray visits the same voxels in reverse order (away from cell-boundary ties).
TEST(VoxelIndex, ReversedRayVisitsTheSameVoxels) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map(2);
  VoxelIndex index(map);
  Rng rng(3);
  std::vector<RayVoxel> a(4096), b(4096);
  std::vector<octomap::OcTreeKey> ka(4096), kb(4096);
  int compared = 0;
  for (int r = 0; r < 200; ++r) {
    const Vec3 o(rng.uniform(0.1, 0.9), rng.uniform(-0.3, 0.5), rng.uniform(0.7, 1.3));
    const Vec3 e(rng.uniform(0.1, 0.9), rng.uniform(-0.3, 0.5), rng.uniform(0.7, 1.3));
    const std::size_t n = index.cast(o, e, o, a.data(), a.size(), nullptr, ka.data());
    const std::size_t m = index.cast(e, o, o, b.data(), b.size(), nullptr, kb.data());
    if (n < 3 || m < 3) continue;
    // Both omit their own end voxel: compare the interior.
    std::vector<octomap::OcTreeKey> fwd(ka.begin() + 1, ka.begin() + long(n));
    std::vector<octomap::OcTreeKey> bwd(kb.begin() + 1, kb.begin() + long(m));
    std::reverse(bwd.begin(), bwd.end());
    if (fwd == bwd) ++compared;
  }
  EXPECT_GE(compared, 190);  // exact ties at voxel corners may differ
}

TEST(VoxelIndex, RefreshFollowsTheRevision) {
  mapping::SemanticOcTree map = nbv_test::scanned_map(1);
  VoxelIndex index(map);
  EXPECT_FALSE(index.refresh(map));
  octomap::OcTreeKey k;
  ASSERT_TRUE(map.key_of(Vec3(2.0, 2.0, 2.0), &k));
  EXPECT_EQ(index.lookup(k), 0u);
  map.update_hit(k, 2);
  EXPECT_TRUE(index.refresh(map));
  EXPECT_NE(index.lookup(k), 0u);
  EXPECT_TRUE(index.info(index.lookup(k)).known);
}

TEST(VoxelIndex, OutsideTheMapVisitsNothing) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map(1);
  VoxelIndex index(map);
  std::vector<RayVoxel> buf(64);
  bool outside = false;
  EXPECT_EQ(index.cast(Vec3(0, 0, 0), Vec3(1e4, 0, 0), Vec3::Zero(), buf.data(), buf.size(), &outside), 0u);
  EXPECT_TRUE(outside);
  // same voxel: nothing
  EXPECT_EQ(index.cast(Vec3(0.5, 0, 1), Vec3(0.501, 0, 1), Vec3::Zero(), buf.data(), buf.size(), &outside), 0u);
  EXPECT_FALSE(outside);
  // capacity bounds the output
  EXPECT_EQ(index.cast(Vec3(0.0, 0, 1), Vec3(0.5, 0, 1), Vec3::Zero(), buf.data(), 5, &outside), 5u);
}

// walk() visits what cast() writes, in order, up to the capacity, stops when told to, and says
// outside when cast() does.
TEST(VoxelIndex, WalkVisitsWhatCastWrites) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map();
  VoxelIndex index(map);
  Rng rng(11);
  std::vector<RayVoxel> buf(4096);
  std::size_t stopped_early = 0, outside_rays = 0;
  for (int r = 0; r < 2000; ++r) {
    const Vec3 o = Vec3(0.5, 0.15, 1.0) + Vec3(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), rng.uniform(-0.4, 0.4));
    Vec3 e = Vec3(0.5, 0.15, 1.0) + Vec3(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
    if (r % 50 == 0) e = o + Vec3(1e4, 0.0, 0.0);  // outside the tree's range
    const std::size_t capacity = r % 7 == 0 ? std::size_t(r % 5) : buf.size();  // 0 and small caps too
    bool outside = false;
    const std::size_t n = index.cast(o, e, o, buf.data(), capacity, &outside);
    // A walk that stops at its first occupied voxel.
    std::vector<const VoxelInfo*> seen;
    const bool inside = index.walk(o, e, capacity, [&](const VoxelInfo& info) {
      seen.push_back(&info);
      return !(info.known && info.p_occ > 0.5f);
    });
    ASSERT_EQ(inside, !outside) << "ray " << r;
    outside_rays += outside;
    std::size_t until = 0;  // what the walk should have visited: cast's voxels to the first occupied one
    while (until < n && !(buf[until].info->known && buf[until].info->p_occ > 0.5f)) ++until;
    if (until < n) ++until;
    ASSERT_EQ(seen.size(), until) << "ray " << r;
    for (std::size_t i = 0; i < until; ++i) ASSERT_EQ(seen[i], buf[i].info) << "ray " << r << " voxel " << i;
    stopped_early += until < n;
  }
  EXPECT_GT(stopped_early, 150u);  // rays through occupied voxels (191 of 2,000 here), not only free and unknown space
  EXPECT_GT(outside_rays, 10u);
}

namespace canopy::nbv {
namespace {

// clear() goes through the map's own mutator: the revision moves and the index follows.
TEST(VoxelIndex, ClearingTheMapRefreshesTheIndex) {
  mapping::SemanticOcTree map = nbv_test::scanned_map(1);
  VoxelIndex index(map);
  ASSERT_GT(index.brick_count(), 0u);
  const std::uint64_t before = map.revision();
  map.clear();
  EXPECT_NE(map.revision(), before);
  EXPECT_TRUE(index.refresh(map));
  EXPECT_EQ(index.brick_count(), 0u);
}

}  // namespace
}  // namespace canopy::nbv

// An index kept up to date with apply_updates() gives, for every voxel, the state a rebuilt
// index gives (ids may differ; equal ids still mean identical states), scan after scan, with
// random hits and pass-throughs that create, change and prune voxels.
TEST(VoxelIndex, IncrementalUpdatesEqualARebuild) {
  mapping::SemanticOcTree map = nbv_test::scanned_map(2);
  VoxelIndex inc(map);
  Rng rng(5);
  for (int batch = 0; batch < 25; ++batch) {
    std::vector<mapping::VoxelUpdate> u;
    for (int i = 0; i < 300; ++i) {
      octomap::OcTreeKey k;
      ASSERT_TRUE(map.key_of(Vec3(rng.uniform(0.35, 0.65), rng.uniform(-0.15, 0.45), rng.uniform(0.85, 1.25)), &k));
      const double r = rng.uniform(0.0, 1.0);
      u.push_back({mapping::morton_code(k), r < 0.5 ? mapping::VoxelUpdate::kFree : std::uint8_t(r < 0.8 ? 2 : 1)});
    }
    std::sort(u.begin(), u.end(), [](const auto& a, const auto& b) { return a.code < b.code; });
    u.erase(std::unique(u.begin(), u.end(), [](const auto& a, const auto& b) { return a.code == b.code; }), u.end());
    const std::uint64_t before = map.revision();
    map.apply_sorted_updates(u);
    ASSERT_TRUE(inc.apply_updates(map, before, u));
    EXPECT_FALSE(inc.refresh(map));  // current: no rebuild
    const VoxelIndex full(map);
    std::size_t known = 0;
    for (int z = -14; z <= 14; ++z)
      for (int y = -22; y <= 22; ++y)
        for (int x = -14; x <= 14; ++x) {
          octomap::OcTreeKey k;
          ASSERT_TRUE(map.key_of(Vec3(0.5 + 0.015 * x, 0.15 + 0.015 * y, 1.05 + 0.015 * z), &k));
          const std::uint32_t a = inc.lookup(k), b = full.lookup(k);
          EXPECT_EQ(a == 0, b == 0);
          known += b != 0;
          expect_same_info(inc.info(a), full.info(b));
        }
    EXPECT_GT(known, 1000u);
  }
  // A batch the index did not see first (another revision) is refused: refresh() rebuilds.
  const std::uint64_t stale = map.revision() - 1;
  EXPECT_FALSE(inc.apply_updates(map, stale, {}));
}

// keep_x() (issue 49): an index that holds only the bricks of a stretch of x, moved along a
// long map and back, answers every lookup and every cast as the full index built incrementally
// from the same batches, with the same palette ids (dropped voxels read from the map), and its
// changed_since() says "changed" whenever the full one does (and exactly as it inside the
// stretch); keep_all() gives back an index equal to the full one everywhere.
TEST(VoxelIndex, AStretchHeldAnswersAsTheFullIndex) {
  mapping::SemanticOcTree map = nbv_test::scanned_map(2);
  VoxelIndex full(map), held(map);
  Rng rng(11);
  // Batches along 6 m of x; the stretch held moves forward, then back over what it dropped.
  const double centres[] = {0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 3.0, 1.0, 5.0, 0.3};
  std::vector<RayVoxel> a(4096), b(4096);
  std::vector<std::uint64_t> bricks_a, bricks_b;
  std::size_t dropped_seen = 0, compared = 0, known = 0, changed_both = 0;
  for (int step = 0; step < 10; ++step) {
    const double c = centres[step];
    held.keep_x(map, c - 0.6, c + 0.6);
    ASSERT_TRUE(held.windowed());
    const std::uint64_t since_full = full.generation(), since_held = held.generation();
    std::vector<mapping::VoxelUpdate> u;
    for (int i = 0; i < 2500; ++i) {
      // mostly near the stretch, a few anywhere (updates where bricks were dropped)
      const double x = i % 10 == 0 ? rng.uniform(0.0, 6.0) : c + rng.uniform(-0.5, 0.5);
      octomap::OcTreeKey k;
      ASSERT_TRUE(map.key_of(Vec3(x, rng.uniform(-0.15, 0.45), rng.uniform(0.85, 1.25)), &k));
      const double r = rng.uniform(0.0, 1.0);
      u.push_back({mapping::morton_code(k), r < 0.5 ? mapping::VoxelUpdate::kFree : std::uint8_t(r < 0.8 ? 2 : 1)});
    }
    std::sort(u.begin(), u.end(), [](const auto& p, const auto& q) { return p.code < q.code; });
    u.erase(std::unique(u.begin(), u.end(), [](const auto& p, const auto& q) { return p.code == q.code; }), u.end());
    const std::uint64_t before = map.revision();
    map.apply_sorted_updates(u);
    ASSERT_TRUE(full.apply_updates(map, before, u));
    ASSERT_TRUE(held.apply_updates(map, before, u));
    dropped_seen = std::max(dropped_seen, held.dropped_bricks());
    EXPECT_LT(held.brick_count(), full.brick_count());
    // Lookups over the whole 6 m (a coarse grid), inside and outside the stretch.
    for (double x = -0.1; x <= 6.1; x += 0.0275)
      for (double y = -0.15; y <= 0.45; y += 0.04)
        for (double z = 0.85; z <= 1.25; z += 0.04) {
          octomap::OcTreeKey k;
          ASSERT_TRUE(map.key_of(Vec3(x, y, z), &k));
          const std::uint32_t ia = full.lookup(k), ib = held.lookup(k);
          ASSERT_EQ(ia, ib) << "x " << x;
          known += ia != 0;
          ++compared;
        }
    // Casts from near the stretch to anywhere, and their bricks' changes since the batch.
    for (int r = 0; r < 300; ++r) {
      const Vec3 o(c + rng.uniform(-0.5, 0.5), rng.uniform(-0.6, 0.6), rng.uniform(0.7, 1.4));
      const Vec3 e(rng.uniform(-0.1, 6.1), rng.uniform(-0.15, 0.45), rng.uniform(0.85, 1.25));
      bricks_a.clear();
      bricks_b.clear();
      const std::size_t na = full.cast(o, e, e, a.data(), a.size(), nullptr, nullptr, &bricks_a);
      const std::size_t nb = held.cast(o, e, e, b.data(), b.size(), nullptr, nullptr, &bricks_b);
      ASSERT_EQ(na, nb);
      ASSERT_EQ(bricks_a, bricks_b);
      for (std::size_t i = 0; i < na; ++i) {
        ASSERT_EQ(a[i].id, b[i].id);
        ASSERT_EQ(a[i].dist2_m2, b[i].dist2_m2);
      }
      std::size_t walked = 0;
      if (nb > 0)
        held.walk(o, e, b.size(), [&](const VoxelInfo& v) {
          EXPECT_EQ(&v, b[walked].info);
          return ++walked < nb;
        });
      const bool ca = full.changed_since(since_full, bricks_a), cb = held.changed_since(since_held, bricks_b);
      if (ca) {
        EXPECT_TRUE(cb);
      }
      changed_both += ca && cb;
      std::vector<std::uint64_t> near;
      for (const std::uint64_t bk : bricks_a) {
        const double bx = (double(bk & 0x1fffu) * 8.0 - 32768.0) * map.getResolution();
        if (bx > c - 0.4 && bx < c + 0.4) near.push_back(bk);
      }
      EXPECT_EQ(full.changed_since(since_full, near), held.changed_since(since_held, near));
    }
  }
  EXPECT_GT(dropped_seen, 100u);
  EXPECT_GT(known, compared / 100);
  EXPECT_GT(changed_both, 100u);
  held.keep_all(map);
  EXPECT_FALSE(held.windowed());
  EXPECT_EQ(held.brick_count(), full.brick_count());
  EXPECT_EQ(held.dropped_bricks(), 0u);
  for (double x = -0.1; x <= 6.1; x += 0.0275)
    for (double y = -0.15; y <= 0.45; y += 0.04)
      for (double z = 0.85; z <= 1.25; z += 0.04) {
        octomap::OcTreeKey k;
        ASSERT_TRUE(map.key_of(Vec3(x, y, z), &k));
        ASSERT_EQ(full.lookup(k), held.lookup(k));
      }
  // A rebuild within a stretch (the next refresh() after a batch the index did not see) holds
  // the stretch's bricks and still answers everywhere.
  VoxelIndex rebuilt;
  rebuilt.keep_x(map, 2.0, 3.0);
  rebuilt.rebuild(map);
  const VoxelIndex fresh(map);
  EXPECT_LT(rebuilt.brick_count(), fresh.brick_count() / 2);
  for (double x = -0.1; x <= 6.1; x += 0.0275)
    for (double y = -0.15; y <= 0.45; y += 0.04) {
      octomap::OcTreeKey k;
      ASSERT_TRUE(map.key_of(Vec3(x, y, 1.05), &k));
      ASSERT_EQ(fresh.lookup(k), rebuilt.lookup(k));
    }
  // And over a map whose far part is moved out (its keep_x(): a long row's mission, when the
  // palette outgrows its bound): the rebuild decodes the moved-out subtrees (their states are
  // interned, as they are read again when the map puts them back) and answers as before.
  map.keep_x(2.0, 3.0);
  ASSERT_GT(map.moved_out(), 0u);
  VoxelIndex over_moved;
  over_moved.keep_x(map, 2.2, 2.8);
  over_moved.rebuild(map);
  std::size_t compared_moved = 0;
  for (double x = 2.0; x <= 3.0; x += 0.0125)
    for (double y = -0.15; y <= 0.45; y += 0.02) {
      octomap::OcTreeKey k;
      ASSERT_TRUE(map.key_of(Vec3(x, y, 1.05), &k));
      ASSERT_EQ(fresh.lookup(k), over_moved.lookup(k)) << "x " << x;
      compared_moved += fresh.lookup(k) != 0;
    }
  EXPECT_GT(compared_moved, 100u);
  EXPECT_GT(map.moved_out(), 0u);
}
