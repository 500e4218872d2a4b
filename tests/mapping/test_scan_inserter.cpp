#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <tuple>

#include "canopy/mapping/scan_inserter.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/common/random.h"
#include "synthetic.h"

using namespace canopy;
using namespace canopy::mapping;
using canopy::perception::LabelledCloud;

namespace {
SemanticOcTree make_inserter_tree(int threads = 1) {
  SemanticMapParams p;
  p.threads = threads;
  return SemanticOcTree(p, SemanticClasses{});
}
constexpr std::uint8_t kFruitLabel = 2;

LabelledCloud one_point(const Vec3& origin, const Vec3& p, std::uint8_t label = kFruitLabel) {
  LabelledCloud c;
  c.origin_world = origin;
  c.points_world.push_back(p.cast<float>());
  c.labels.push_back(label);
  return c;
}

std::set<std::uint64_t> codes(const std::vector<octomap::OcTreeKey>& keys) {
  std::set<std::uint64_t> out;
  for (const auto& k : keys) out.insert(morton_code(k));
  return out;
}
}  // namespace

TEST(ScanInserter, OneHitAndItsRayGiveExactLogOdds) {
  SemanticOcTree map = make_inserter_tree();
  ScanInserter ins(map);
  const Vec3 origin(0.0, 0.0, 1.0), p(0.5, 0.0, 1.0);
  const InsertStats st = ins.insert(one_point(origin, p));
  EXPECT_EQ(st.hit_voxels, 1u);
  EXPECT_EQ(st.rays, 1u);
  const SemanticState* hit = map.find(p);
  ASSERT_NE(hit, nullptr);
  EXPECT_EQ(hit->count, 1);
  EXPECT_EQ(hit->logodds[0], 1.0f);
  EXPECT_EQ(hit->others, -0.1f);
  const SemanticState* free = map.find(Vec3(0.25, 0.0, 1.0));
  ASSERT_NE(free, nullptr);
  EXPECT_EQ(free->count, 0);
  EXPECT_EQ(free->others, -0.1f);
  // A second scan through the hit voxel from the other side: it becomes free-updated once.
  ins.insert(one_point(Vec3(1.0, 0.0, 1.0), Vec3(0.2, 0.0, 1.0)));
  EXPECT_EQ(map.find(p)->logodds[0], 1.0f + -0.1f);
  EXPECT_EQ(map.find(p)->others, -0.1f + -0.1f);
}

// The fast ray kernel visits exactly the voxels OctoMap's computeRayKeys visits.
TEST(ScanInserter, FreeSpaceRayCarvesOnlyItsCells) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    SemanticOcTree map = make_inserter_tree();
    ScanInserter ins(map);
    const Vec3 origin(u(rng) * 0.3, u(rng) * 0.3, 1.0 + u(rng) * 0.3);
    Vec3 dir(u(rng), u(rng), u(rng));
    dir.normalize();
    const double len = 0.05 + 1.25 * (0.5 + 0.5 * u(rng));  // some beyond the 1.0 m max range
    const Vec3 p = origin + dir * len;
    std::vector<VoxelUpdate> updates;
    InsertStats st;
    ins.compute_updates(one_point(origin, p), &updates, &st);
    // Reference: segment to the endpoint voxel's centre, cut at the ray range.
    octomap::OcTreeKey kp;
    ASSERT_TRUE(map.key_of(p, &kp));
    Vec3 end = map.center_of(kp);
    const octomap::point3d of(float(origin.x()), float(origin.y()), float(origin.z()));
    const octomap::point3d cf(float(end.x()), float(end.y()), float(end.z()));
    if ((cf - of).norm() > 0.8) {
      const octomap::point3d e = of + (cf - of).normalized() * 0.8f;
      end = Vec3(e.x(), e.y(), e.z());
    }
    std::vector<octomap::OcTreeKey> ref;
    ASSERT_TRUE(ray_free_keys(map, origin, end, &ref));
    std::set<std::uint64_t> expected = codes(ref);
    expected.erase(morton_code(kp));  // the hit is never free
    std::set<std::uint64_t> got;
    for (const auto& up : updates)
      if (up.label == VoxelUpdate::kFree) got.insert(up.code);
    EXPECT_EQ(got, expected) << "trial " << trial;
    const bool is_hit = len <= map.params().max_range_m;
    EXPECT_EQ(st.hit_voxels, is_hit ? 1u : 0u);
  }
}

TEST(ScanInserter, RayRangeAndMaxRange) {
  SemanticOcTree map = make_inserter_tree();
  ScanInserter ins(map);
  const Vec3 origin(0.0, 0.0, 1.0);
  // Endpoint at 0.95 m: a hit (within 1.0 m) but free space stops at 0.8 m.
  ins.insert(one_point(origin, origin + Vec3(0.95, 0, 0)));
  EXPECT_NE(map.find(origin + Vec3(0.95, 0, 0)), nullptr);
  EXPECT_NE(map.find(origin + Vec3(0.78, 0, 0)), nullptr);
  EXPECT_EQ(map.find(origin + Vec3(0.85, 0, 0)), nullptr);
  // Endpoint at 1.2 m: no hit, free space up to 0.8 m only.
  SemanticOcTree map2 = make_inserter_tree();
  ScanInserter ins2(map2);
  const InsertStats st = ins2.insert(one_point(origin, origin + Vec3(0, 1.2, 0)));
  EXPECT_EQ(st.beyond_range, 1u);
  EXPECT_EQ(st.hit_voxels, 0u);
  EXPECT_EQ(map2.find(origin + Vec3(0, 1.2, 0)), nullptr);
  EXPECT_NE(map2.find(origin + Vec3(0, 0.7, 0)), nullptr);
}

TEST(ScanInserter, HitsAreExcludedFromFreeAndVoxelFilteredByMajority) {
  SemanticOcTree map = make_inserter_tree();
  ScanInserter ins(map);
  LabelledCloud c;
  c.origin_world = Vec3(0, 0, 1);
  // Two voxels on the same line: the nearer one is hit, the ray to the farther one passes it.
  const Vec3 near(0.3, 0.0, 1.0), far(0.6, 0.0, 1.0);
  for (int i = 0; i < 3; ++i) {
    c.points_world.push_back(near.cast<float>());
    c.labels.push_back(i < 2 ? 1 : 2);  // majority leaf
  }
  c.points_world.push_back(far.cast<float>());
  c.labels.push_back(2);
  const InsertStats st = ins.insert(c);
  EXPECT_EQ(st.hit_voxels, 2u);
  EXPECT_EQ(st.rays, 2u);
  const SemanticState* n = map.find(near);
  ASSERT_NE(n, nullptr);
  EXPECT_EQ(n->most_likely_class(), 1);
  EXPECT_EQ(n->logodds[0], 1.0f);  // one hit, no free update in the same scan
  EXPECT_EQ(map.find(far)->most_likely_class(), 2);
}

TEST(ScanInserter, BadPointsAndLabelsAreSkippedAndCounted) {
  SemanticOcTree map = make_inserter_tree();
  ScanInserter ins(map);
  LabelledCloud c;
  c.origin_world = Vec3(0, 0, 1);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  c.points_world = {Vec3f(nan, 0, 1), Vec3f(0.3f, inf, 1), Vec3f(0.3f, 0, 1), Vec3f(0.3f, 0.1f, 1), Vec3f(1e6f, 0, 0)};
  c.labels = {1, 1, 7, 2, 1};
  const InsertStats st = ins.insert(c);
  EXPECT_EQ(st.bad_point, 2u);
  EXPECT_EQ(st.bad_label, 1u);
  EXPECT_EQ(st.outside_map, 1u);
  EXPECT_EQ(st.skipped(), 4u);
  EXPECT_EQ(st.hit_voxels, 1u);
  EXPECT_EQ(map.find(Vec3(0.3, 0.0, 1.0)), nullptr);  // the bad-label point left no hit
}

// One or two threads give the identical map, on scans big enough to take every parallel
// path (points, rays, free-space grid cells and the tree update all above their thresholds).
TEST(ScanInserter, ThreadCountDoesNotChangeTheMap) {
  auto params = [](int threads) {
    SemanticMapParams p;
    p.threads = threads;
    p.max_range_m = 3.0;
    p.ray_range_m = 3.0;
    return p;
  };
  SemanticOcTree a(params(1), SemanticClasses{}), b(params(2), SemanticClasses{});
  ScanInserter ia(a), ib(b);
  Rng rng(21);
  for (int scan = 0; scan < 2; ++scan) {
    LabelledCloud cloud;
    cloud.origin_world = Vec3(0.0, 0.1 * scan, 0.0);
    for (int i = 0; i < 150000; ++i) {
      cloud.points_world.push_back(
          Vec3f(float(rng.uniform(-1.25, 1.25)), float(rng.uniform(-1.25, 1.25)), float(rng.uniform(0.3, 1.4))));
      cloud.labels.push_back(static_cast<std::uint8_t>(rng.integer(0, 2)));
    }
    const InsertStats sa = ia.insert(cloud);
    const InsertStats sb = ib.insert(cloud);
    EXPECT_GE(sa.points, 100000u);
    EXPECT_GE(sa.rays, 8192u);
    EXPECT_GE(sa.hit_voxels + sa.free_voxels, 32768u);
    EXPECT_EQ(sa.free_voxels, sb.free_voxels);
    EXPECT_EQ(sa.hit_voxels, sb.hit_voxels);
  }
  // Same leaves (pruned blocks included) with the same states; params differ in `threads`.
  auto leaves = [](const SemanticOcTree& m) {
    std::vector<std::tuple<std::uint64_t, unsigned, SemanticState>> out;
    m.for_each_leaf([&](const octomap::OcTreeKey& key, unsigned depth, const SemanticState& st) {
      out.emplace_back(morton_code(key), depth, st);
    });
    return out;
  };
  const auto la = leaves(a), lb = leaves(b);
  EXPECT_EQ(a.size(), b.size());
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t i = 0; i < la.size(); ++i) {
    EXPECT_EQ(std::get<0>(la[i]), std::get<0>(lb[i]));
    EXPECT_EQ(std::get<1>(la[i]), std::get<1>(lb[i]));
    EXPECT_TRUE(std::get<2>(la[i]) == std::get<2>(lb[i]));
  }
  EXPECT_GT(la.size(), 10000u);
}

// Rays too long for the dense grid take the sort-and-deduplicate path: same cells.
TEST(ScanInserter, LongRaysUseTheFallbackWithTheSameCells) {
  SemanticMapParams p;
  p.max_range_m = 20.0;
  p.ray_range_m = 20.0;
  SemanticOcTree map(p, SemanticClasses{});
  ScanInserter ins(map);
  const Vec3 origin(0.0, 0.0, 1.0), end(7.003, 7.207, 7.111);  // box of ~470^3 cells > the grid cap
  std::vector<VoxelUpdate> updates;
  InsertStats st;
  ins.compute_updates(one_point(origin, end), &updates, &st);
  octomap::OcTreeKey kp;
  ASSERT_TRUE(map.key_of(end, &kp));
  std::vector<octomap::OcTreeKey> ref;
  ASSERT_TRUE(ray_free_keys(map, origin, map.center_of(kp), &ref));
  std::set<std::uint64_t> expected = codes(ref), got;
  for (const auto& u : updates)
    if (u.label == VoxelUpdate::kFree) got.insert(u.code);
  EXPECT_EQ(got, expected);
  EXPECT_GT(got.size(), 500u);
  EXPECT_EQ(st.hit_voxels, 1u);
}
