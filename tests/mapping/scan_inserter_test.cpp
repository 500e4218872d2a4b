#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <array>
#include <random>
#include <set>
#include <tuple>

#include "canopy/mapping/scan_inserter.h"
#include "canopy/mapping/voxel_ray.h"
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

// The voxel filter counts every point of a voxel, however its points are spread: runs of one
// to five points of a (voxel, label) shuffled among the others, counts far beyond a run's 254,
// the chunks of the parallel path. Each voxel's labels differ by 0-3 points in about 3,000, so
// a point lost or counted twice changes the answer; ties go to the smaller class.
TEST(ScanInserter, MajorityLabelsEqualABruteForceCount) {
  for (const int threads : {1, 2}) {
    SemanticOcTree map = make_inserter_tree(threads);
    ScanInserter ins(map);
    LabelledCloud c;
    c.origin_world = Vec3(0.0, 0.0, 1.0);
    Rng rng(23);
    struct Run {
      Vec3 centre;
      std::uint8_t label;
      int length;
    };
    std::vector<Run> runs;
    std::map<std::uint64_t, std::array<int, 3>> counts;  // per voxel code: points per label
    for (int v = 0; v < 12; ++v) {
      octomap::OcTreeKey key;
      ASSERT_TRUE(map.key_of(Vec3(0.5, -0.09 + 0.015 * v, 1.0 + 0.02 * (v % 3)), &key));
      const Vec3 centre = map.center_of(key);
      for (std::uint8_t label = 0; label < 3; ++label) {
        int left = 3000 + rng.integer(0, 3);
        counts[morton_code(key)][label] = left;
        while (left > 0) {
          const int len = std::min(left, rng.integer(1, 5));
          runs.push_back({centre, label, len});
          left -= len;
        }
      }
    }
    for (std::size_t i = runs.size(); i > 1; --i) std::swap(runs[i - 1], runs[std::size_t(rng.integer(0, int(i) - 1))]);
    for (const Run& r : runs)
      for (int k = 0; k < r.length; ++k) {
        c.points_world.push_back((r.centre + Vec3(rng.uniform(-0.005, 0.005), rng.uniform(-0.005, 0.005), 0.0)).cast<float>());
        c.labels.push_back(r.label);
      }
    ASSERT_GT(c.points_world.size(), 100000u);  // the parallel path's size
    std::vector<VoxelUpdate> updates;
    InsertStats st;
    ins.compute_updates(c, &updates, &st);
    std::map<std::uint64_t, int> got;
    for (const VoxelUpdate& u : updates)
      if (u.label != VoxelUpdate::kFree) got[u.code] = u.label;
    std::map<std::uint64_t, int> expected;
    for (const auto& [code, n] : counts)
      expected[code] = int(std::max_element(n.begin(), n.end()) - n.begin());  // the first of equal maxima
    EXPECT_EQ(got, expected) << threads << " thread(s)";
  }
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

// An inserter keeps its scratch grids between scans: what one scan leaves in them must not
// change the next. Scan after scan (boxes that grow, shrink and move; many rays and few; one
// thread and two), a reused inserter gives the updates of a fresh one on the same map.
TEST(ScanInserter, ReusedInserterGivesAFreshInsertersUpdates) {
  for (const int threads : {1, 2}) {
    SemanticMapParams p;
    p.threads = threads;
    SemanticOcTree map(p, SemanticClasses{});
    ScanInserter reused(map);
    Rng rng(5 + threads);
    for (int scan = 0; scan < 6; ++scan) {
      LabelledCloud cloud;
      cloud.origin_world = Vec3(0.3 * scan, -0.2 * (scan % 2), 1.0);
      const int n = scan % 3 == 2 ? 3000 : 60000;  // few rays: one grid; many: one per thread
      const double spread = scan % 2 == 0 ? 0.8 : 0.3;
      for (int i = 0; i < n; ++i) {
        Vec3 d(rng.uniform(-spread, spread), rng.uniform(-spread, spread), -1.0);
        d.normalize();
        cloud.points_world.push_back((cloud.origin_world + rng.uniform(0.2, 0.9) * d).cast<float>());
        cloud.labels.push_back(static_cast<std::uint8_t>(rng.integer(0, 2)));
      }
      ScanInserter fresh(map);
      std::vector<VoxelUpdate> a, b;
      InsertStats sa, sb;
      fresh.compute_updates(cloud, &b, &sb);
      reused.compute_updates(cloud, &a, &sa);
      ASSERT_GT(sb.free_voxels, 1000u);
      if (n > 8192) {
        ASSERT_GT(sb.rays, 8192u) << "scan " << scan << " must take the parallel path";
      } else {
        ASSERT_LT(sb.rays, 8192u) << "scan " << scan << " must take the one-grid path";
      }
      ASSERT_EQ(a.size(), b.size()) << "threads " << threads << ", scan " << scan;
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].code, b[i].code) << "threads " << threads << ", scan " << scan << ", update " << i;
        ASSERT_EQ(a[i].label, b[i].label) << "threads " << threads << ", scan " << scan << ", update " << i;
      }
      reused.insert(cloud);  // the map moves on, and the grids are used once more
    }
  }
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

// --- Protocol options of issue 19 -------------------------------------------------------------

namespace {
// A 5 x 5 frame looking along world +x from (0, 0, 1): the centre pixel sees a fruit 0.5 m
// away, every other pixel has no depth return (0) or an invalid one (NaN, inf).
LabelledFrame no_return_frame() {
  LabelledFrame f;
  f.intrinsics.width_px = f.intrinsics.height_px = 5;
  f.intrinsics.fx_px = f.intrinsics.fy_px = 10.0;  // wide pixels: 0.1 rad apart
  f.intrinsics.cx_px = f.intrinsics.cy_px = 2.5;
  Eigen::Matrix3d R;  // camera z = world x, camera x = world -y, camera y = world -z
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  f.T_world_camera = Pose::Identity();
  f.T_world_camera.linear() = R;
  f.T_world_camera.translation() = Vec3(0.0, 0.0, 1.0);
  f.depth_m = Image<float>(5, 5, 0.f);
  f.depth_m.at(0, 0) = std::numeric_limits<float>::quiet_NaN();
  f.depth_m.at(4, 4) = std::numeric_limits<float>::infinity();
  f.depth_m.at(2, 2) = 0.5f;
  f.class_id = Image<std::uint8_t>(5, 5, 0);
  f.class_id.at(2, 2) = kFruitLabel;
  f.instance = Image<std::int32_t>(5, 5, -1);
  f.rgb = Image<Rgb8>(5, 5, Rgb8{0, 0, 0});
  return f;
}
}  // namespace

// missing_depth: carve. A pixel without a return becomes a point 3.0 m along its ray, beyond
// the 1.0 m max range: no hit, and its ray carves free space to the 0.8 m ray range, exactly
// the cells OctoMap's computeRayKeys gives for that segment; with skip they stay unknown.
TEST(ScanInserter, MissingDepthCarvesItsRaysToTheRayRange) {
  const LabelledFrame f = no_return_frame();
  perception::ExtractorParams ep;
  ep.source = perception::LabelSource::kTruth;
  ep.p_gt = 1.0;
  EXPECT_EQ(ep.missing_depth, perception::MissingDepth::kCarve);  // the default: the released code's
  EXPECT_EQ(ep.missing_depth_m, 3.0);
  perception::SemanticExtractor carve(ep, SemanticClasses{});
  const LabelledCloud c = carve.extract(f);
  EXPECT_EQ(c.stats.missing_depth, 24u);
  EXPECT_EQ(c.stats.bad_depth, 0u);
  ASSERT_EQ(c.size(), 25u);

  SemanticOcTree map = make_inserter_tree();
  ScanInserter ins(map);
  std::vector<VoxelUpdate> updates;
  InsertStats st;
  ins.compute_updates(c, &updates, &st);
  EXPECT_EQ(st.beyond_range, 24u);
  EXPECT_EQ(st.hit_voxels, 1u);
  // The expected free cells: every pixel's segment (no return: to 0.8 m towards its 3.0 m
  // point's voxel centre; the fruit: to its voxel's centre), less the fruit's voxel.
  std::set<std::uint64_t> expected;
  octomap::OcTreeKey fruit_key;
  ASSERT_TRUE(map.key_of(c.points_world[12].cast<double>(), &fruit_key));
  const octomap::point3d of(0.f, 0.f, 1.f);
  for (std::size_t i = 0; i < c.size(); ++i) {
    octomap::OcTreeKey k;
    ASSERT_TRUE(map.key_of(c.points_world[i].cast<double>(), &k));
    const Vec3 centre = map.center_of(k);
    const octomap::point3d cf(float(centre.x()), float(centre.y()), float(centre.z()));
    octomap::point3d e = cf;
    if (i != 12) {
      EXPECT_NEAR((c.points_world[i].cast<double>() - Vec3(0, 0, 1)).x(), 3.0, 1e-5);  // planar depth 3.0 along x
      e = of + (cf - of).normalized() * 0.8f;
    }
    std::vector<octomap::OcTreeKey> keys;
    ASSERT_TRUE(ray_free_keys(map, Vec3(0, 0, 1), Vec3(e.x(), e.y(), e.z()), &keys));
    for (const std::uint64_t code : codes(keys)) expected.insert(code);
  }
  expected.erase(morton_code(fruit_key));
  std::set<std::uint64_t> got;
  for (const auto& up : updates)
    if (up.label == VoxelUpdate::kFree) got.insert(up.code);
  EXPECT_EQ(got, expected);
  EXPECT_GT(got.size(), 24u * 40u);  // 24 rays of about 53 cells, shared near the camera

  // In the map: a cell on a no-return ray before 0.8 m is free, one beyond it unknown.
  ins.insert(c);
  const Vec3 dir = (c.points_world[0].cast<double>() - Vec3(0, 0, 1)).normalized();
  const SemanticState* near = map.find(Vec3(0, 0, 1) + 0.7 * dir);
  ASSERT_NE(near, nullptr);
  EXPECT_EQ(near->count, 0);
  EXPECT_EQ(near->others, -0.1f);
  EXPECT_EQ(map.find(Vec3(0, 0, 1) + 0.85 * dir), nullptr);
  EXPECT_EQ(map.find(Vec3(0, 0, 1) + 2.99 * dir), nullptr);

  // skip: the same frame carves only the fruit pixel's ray.
  ep.missing_depth = perception::MissingDepth::kSkip;
  perception::SemanticExtractor skip(ep, SemanticClasses{});
  const LabelledCloud s = skip.extract(f);
  EXPECT_EQ(s.stats.bad_depth, 24u);
  EXPECT_EQ(s.stats.missing_depth, 0u);
  ASSERT_EQ(s.size(), 1u);
  SemanticOcTree map2 = make_inserter_tree();
  ScanInserter ins2(map2);
  ins2.insert(s);
  EXPECT_EQ(map2.find(Vec3(0, 0, 1) + 0.7 * dir), nullptr);
  ASSERT_NE(map2.find(c.points_world[12].cast<double>()), nullptr);
  EXPECT_EQ(map2.find(c.points_world[12].cast<double>())->logodds[0], 1.0f);
}

// insertion: per_endpoint. The camera at a voxel centre puts the filter's cell corners half a
// voxel off the map's, so one map voxel overlaps 8 filter cells: k points in k different cells
// of one voxel are k hits, l_fruit = k psi and l_others = k phi; two points in one cell
// are one hit; mixed labels are applied most frequent first, as k sequential SSMI updates.
TEST(ScanInserter, PerEndpointInsertionGivesOneHitPerFilteredPoint) {
  SemanticMapParams p;
  p.threads = 1;
  p.insertion = Insertion::kPerEndpoint;
  const double r = p.resolution_m;
  // The camera at a voxel's centre, the voxel 20 voxels ahead of it (R = identity: along x).
  Vec3 origin;
  octomap::OcTreeKey vk;
  {
    SemanticOcTree probe(p, SemanticClasses{});
    octomap::OcTreeKey ok;
    ASSERT_TRUE(probe.key_of(Vec3(0.0, 0.0, 1.0), &ok));
    origin = probe.center_of(ok);
    vk = ok;
    vk[0] = static_cast<octomap::key_type>(ok[0] + 20);
  }
  // The 8 sub-cubes of the voxel: each lies in a different filter cell.
  const auto sub_point = [&](const SemanticOcTree& m, int o) {
    const Vec3 c = m.center_of(vk);
    Vec3 q;
    for (int a = 0; a < 3; ++a) q[a] = c[a] + ((o >> a) & 1 ? 0.25 * r : -0.25 * r);
    return q;
  };
  for (int k = 1; k <= 8; ++k) {
    SemanticOcTree map(p, SemanticClasses{});
    ScanInserter ins(map);
    LabelledCloud c;
    c.origin_world = origin;
    for (int o = 0; o < k; ++o) {
      c.points_world.push_back(sub_point(map, o).cast<float>());
      c.labels.push_back(kFruitLabel);
    }
    const InsertStats st = ins.insert(c);
    EXPECT_EQ(st.hit_voxels, 1u);
    EXPECT_EQ(st.hit_updates, std::size_t(k));
    const SemanticState* s = map.find(vk);
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(s->count, 1);
    EXPECT_EQ(s->class_id[0], kFruitLabel);
    EXPECT_NEAR(s->logodds[0], k * 1.0, 1e-5) << k;
    EXPECT_NEAR(s->others, k * -0.1, 1e-5) << k;  // each hit adds phi to the others bucket
    // per_voxel: the same cloud is one hit.
    SemanticMapParams pv = p;
    pv.insertion = Insertion::kPerVoxel;
    SemanticOcTree map_pv(pv, SemanticClasses{});
    ScanInserter ins_pv(map_pv);
    ins_pv.insert(c);
    EXPECT_EQ(map_pv.find(vk)->logodds[0], 1.0f);
  }
  // Four points inside one sub-cube: one filter cell, one point (their centroid), one hit.
  {
    SemanticOcTree map(p, SemanticClasses{});
    ScanInserter ins(map);
    LabelledCloud c;
    c.origin_world = origin;
    for (int i = 0; i < 4; ++i) {
      Vec3 q = sub_point(map, 0);
      q.x() += 0.05 * r * i;
      c.points_world.push_back(q.cast<float>());
      c.labels.push_back(kFruitLabel);
    }
    EXPECT_EQ(ins.insert(c).hit_updates, 1u);
    EXPECT_EQ(map.find(vk)->logodds[0], 1.0f);
  }
  // Mixed labels: 3 fruit cells and 2 leaf cells = 5 SSMI hits, fruit first.
  {
    SemanticOcTree map(p, SemanticClasses{});
    ScanInserter ins(map);
    LabelledCloud c;
    c.origin_world = origin;
    const std::uint8_t leaf = 1;
    for (int o = 0; o < 5; ++o) {
      c.points_world.push_back(sub_point(map, o).cast<float>());
      c.labels.push_back(o == 1 || o == 3 ? leaf : kFruitLabel);
    }
    EXPECT_EQ(ins.insert(c).hit_updates, 5u);
    SemanticState ref;
    for (int c_ : {int(kFruitLabel), int(kFruitLabel), int(kFruitLabel), int(leaf), int(leaf)}) ref.apply_hit(c_, p.rule());
    EXPECT_EQ(*map.find(vk), ref);
    EXPECT_EQ(map.find(vk)->most_likely_class(), kFruitLabel);
  }
}

// last_occupancy() equals looking each updated voxel up before and after the scan, with both
// insertions (per_endpoint applies further hits in layers after the first batch).
TEST(ScanInserter, LastOccupancyEqualsLookupsBeforeAndAfterTheScan) {
  for (const Insertion insertion : {Insertion::kPerVoxel, Insertion::kPerEndpoint}) {
    SemanticMapParams p;
    p.threads = 1;
    p.insertion = insertion;
    SemanticOcTree map(p, SemanticClasses{});
    ScanInserter ins(map);
    Rng rng(5);
    std::size_t changed = 0;
    for (int scan = 0; scan < 6; ++scan) {
      LabelledCloud cloud;
      cloud.origin_world = Vec3(0.02 * scan, 0.0, 0.0);
      cloud.R_world_camera = Eigen::Matrix3d::Identity();
      // Points on a few small patches (many hits per voxel) and a wider scatter.
      for (int i = 0; i < 20000; ++i) {
        const bool patch = i % 2 == 0;
        const double s = patch ? 0.03 : 0.4;
        cloud.points_world.push_back(Vec3f(float(rng.uniform(-s, s)), float(rng.uniform(-s, s)),
                                           float(patch ? 0.5 + 0.1 * (i % 3) : rng.uniform(0.3, 0.9))));
        cloud.labels.push_back(static_cast<std::uint8_t>(rng.integer(0, 2)));
      }
      const SemanticOcTree before = map;
      ins.insert(cloud);
      const auto& updates = ins.last_updates();
      const auto& occupancy = ins.last_occupancy();
      ASSERT_EQ(occupancy.size(), updates.size());
      auto occupied = [](const SemanticOcTree& m, std::uint64_t code) {
        const SemanticState* s = m.find(morton_key(code));
        return s && s->occupancy_logodds() > 0.f;
      };
      for (std::size_t i = 0; i < updates.size(); ++i) {
        const bool b = occupied(before, updates[i].code), a = occupied(map, updates[i].code);
        ASSERT_EQ(bool(occupancy[i] & SemanticOcTree::kOccupiedBefore), b) << "scan " << scan << ", update " << i;
        ASSERT_EQ(bool(occupancy[i] & SemanticOcTree::kOccupiedAfter), a) << "scan " << scan << ", update " << i;
        changed += a != b;
      }
    }
    EXPECT_GT(changed, 100u) << (insertion == Insertion::kPerEndpoint ? "per_endpoint" : "per_voxel");
  }
}

namespace {

// Where the ray-walk tests' segments start: a third of them here, the others anywhere.
const octomap::point3d kWalkOrigin(0.31f, -0.77f, 1.03f);

// 3000 segments up to 0.8 m long: random, axis-aligned, in a plane through voxel edges, within
// one voxel, and one that leaves the tree.
std::vector<std::pair<octomap::point3d, octomap::point3d>> walk_segments() {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<octomap::point3d, octomap::point3d>> segs;
  const octomap::point3d o = kWalkOrigin;
  for (int i = 0; i < 3000; ++i) {
    octomap::point3d a = i % 3 == 0 ? o : octomap::point3d(float(u(rng)), float(u(rng)), float(1.0 + u(rng)));
    octomap::point3d d(float(u(rng)), float(u(rng)), float(u(rng)));
    if (i % 11 == 0) d = octomap::point3d(0.f, 0.f, i % 2 ? 1.f : -1.f);  // along an axis
    if (i % 13 == 0) d = octomap::point3d(1.f, i % 2 ? 1.f : -1.f, 0.f);  // in a plane, through edges
    d.normalize();
    float len = float(0.8 * (0.5 + 0.5 * u(rng)));
    if (i % 17 == 0) len = 0.002f;  // often within one voxel
    if (i == 5) len = 1e5f;         // leaves the tree
    segs.emplace_back(a, a + d * len);
  }
  return segs;
}

}  // namespace

// walk_rays (four rays per AVX2 register where the processor has them) visits each segment's
// voxels exactly as walk_ray does: the same multiset of visits, on random, axis-aligned,
// one-voxel and outside-the-tree segments; and so does its one-ray-at-a-time fallback.
TEST(VoxelRay, BatchWalkVisitsWhatEachWalkVisits) {
  SemanticOcTree map = make_inserter_tree();
  const auto segs = walk_segments();
  std::vector<std::uint64_t> expected;
  for (const auto& [a, b] : segs)
    walk_ray(map, a, b, [&](unsigned x, unsigned y, unsigned z) {
      expected.push_back(morton_code(octomap::OcTreeKey(static_cast<octomap::key_type>(x),
                                                        static_cast<octomap::key_type>(y),
                                                        static_cast<octomap::key_type>(z))));
      return true;
    });
  std::sort(expected.begin(), expected.end());
  ASSERT_GT(expected.size(), 50000u);
  for (const bool vectorised : {true, false}) {
    std::vector<std::uint64_t> got;
    walk_rays(
        map, segs.size(),
        [&](std::size_t i, octomap::point3d* a, octomap::point3d* b) {
          *a = segs[i].first;
          *b = segs[i].second;
        },
        [&](unsigned x, unsigned y, unsigned z) {
          got.push_back(morton_code(octomap::OcTreeKey(static_cast<octomap::key_type>(x),
                                                       static_cast<octomap::key_type>(y),
                                                       static_cast<octomap::key_type>(z))));
        },
        vectorised);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << (vectorised ? "vectorised" : "one ray at a time");
  }
}

// mark_walked_voxels marks exactly the voxels walk_ray visits that lie in the grid's box, in
// AVX2 lanes and one ray at a time, also when the box holds only part of the walks (lanes
// outside it in x, y or z, below and above) and rays that start or end outside it.
TEST(VoxelRay, BitGridMarksTheWalkedVoxelsInItsBoxOnly) {
  SemanticOcTree map = make_inserter_tree();
  const auto segs = walk_segments();
  octomap::OcTreeKey ko;
  ASSERT_TRUE(map.coordToKeyChecked(kWalkOrigin, ko));
  KeyBitGrid box;  // about a quarter of the walks' extent around the origin, off centre
  box.lo[0] = int(ko[0]) - 7;
  box.lo[1] = int(ko[1]) - 12;
  box.lo[2] = int(ko[2]) - 4;
  box.n[0] = 19, box.n[1] = 15, box.n[2] = 23;
  std::vector<std::uint8_t> expected(box.size(), 0);
  long outside = 0;
  for (const auto& [a, b] : segs)
    walk_ray(map, a, b, [&](unsigned x, unsigned y, unsigned z) {
      const int i = int(x) - box.lo[0], j = int(y) - box.lo[1], k = int(z) - box.lo[2];
      if (i < 0 || j < 0 || k < 0 || i >= box.n[0] || j >= box.n[1] || k >= box.n[2]) {
        ++outside;
      } else {
        expected[(std::size_t(k) * box.n[1] + j) * box.n[0] + i] = 1;
      }
      return true;
    });
  ASSERT_GT(outside, 20000);  // most of the walks leave the box
  ASSERT_GT(std::count(expected.begin(), expected.end(), 1), 500);
  for (const bool vectorised : {true, false}) {
    std::vector<std::uint64_t> words(box.word_count() + 8, 0);  // margins that must stay untouched
    KeyBitGrid g = box;
    g.words = words.data() + 4;
    mark_walked_voxels(
        map, segs.size(),
        [&](std::size_t i, octomap::point3d* a, octomap::point3d* b) {
          *a = segs[i].first;
          *b = segs[i].second;
        },
        g, vectorised);
    std::vector<std::uint8_t> got(box.size(), 0);
    for (std::size_t c = 0; c < box.size(); ++c) got[c] = (g.words[c / 64] >> (c % 64)) & 1;
    EXPECT_EQ(got, expected) << (vectorised ? "lanes" : "one at a time");
    EXPECT_EQ(std::count(words.begin(), words.begin() + 4, 0), 4);
    EXPECT_EQ(std::count(words.end() - 4, words.end(), 0), 4);
    ASSERT_NE(box.size() % 64, 0u);  // the last word's bits past the box stay clear
    EXPECT_EQ(g.words[box.word_count() - 1] >> (box.size() % 64), 0u);
  }
}

// The inserter's updates do not depend on how its rays are walked (lanes or one at a time),
// with missing depth carving long rays.
TEST(ScanInserter, VectorisedRaysGiveTheSameUpdates) {
  SemanticMapParams p;
  p.threads = 2;
  SemanticOcTree map(p, SemanticClasses{});
  ScanInserter lanes(map), single(map);
  single.set_vectorised(false);
  Rng rng(9);
  LabelledCloud cloud;
  cloud.origin_world = Vec3(0.05, -0.02, 1.0);
  for (int i = 0; i < 120000; ++i) {
    const double r = i % 3 == 0 ? 4.0 : rng.uniform(0.2, 0.9);  // a third far beyond max range
    Vec3 d(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), 1.0);
    d.normalize();
    cloud.points_world.push_back((cloud.origin_world + r * d).cast<float>());
    cloud.labels.push_back(static_cast<std::uint8_t>(rng.integer(0, 2)));
  }
  std::vector<VoxelUpdate> a, b;
  InsertStats sa, sb;
  lanes.compute_updates(cloud, &a, &sa);
  single.compute_updates(cloud, &b, &sb);
  EXPECT_GT(sa.rays, 8192u);  // the parallel path
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].code, b[i].code) << i;
    ASSERT_EQ(a[i].label, b[i].label) << i;
  }
  EXPECT_GT(sa.free_voxels, 10000u);
}
