// The view features of a learned scorer (nbv/view_features.h) on the shape planner's scene: one
// fruit mapped from the front only, a leaf beside its back on the +y side. The features agree
// with what they restate (the shape planner's score, each gain evaluated on its own), and the
// geometric ones tell the unseen back from the seen front.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

#include "../mapping/synthetic.h"
#include "scene.h"
#include "canopy/common/random.h"
#include "canopy/nbv/planners/shape/shape.h"
#include "canopy/nbv/view_evaluator.h"
#include "canopy/nbv/view_features.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

const Vec3 kFruit = nbv_test::kShapeFruit;
const Eigen::AlignedBox3d kRegion(Vec3(0.2, -0.4, 0.6), Vec3(0.8, 0.4, 1.4));

mapping::SemanticOcTree front_map() { return nbv_test::front_map(true); }

std::size_t feature(const std::string& name) {
  const auto& n = view_feature_names();
  const auto it = std::find(n.begin(), n.end(), name);
  EXPECT_NE(it, n.end()) << name;
  return std::size_t(it - n.begin());
}

TEST(ViewFeatures, NamesAreUniqueAndEveryGainOfTheRegistryButRandomIsOne) {
  const auto& n = view_feature_names();
  EXPECT_EQ(std::set<std::string>(n.begin(), n.end()).size(), n.size());
  for (const GainEntry& g : gain_registry()) {
    const std::string name = g.uses_proximity ? g.name + "_per_voxel@ours" : g.name + "@ours";
    EXPECT_EQ(std::count(n.begin(), n.end(), name), g.name == "rs" ? 0 : 1) << name;
  }
}

// shape_seen is the shape planner's score of the same candidate; every gain feature is that
// gain evaluated alone (one cast of the rays for all of them gives the same sums).
TEST(ViewFeatures, AgreeWithTheShapePlannerAndWithEachGainAlone) {
  const mapping::SemanticOcTree map = front_map();
  VoxelIndex index(map);
  ViewPlannerSettings s;
  s.method.name = "shape";
  const auto planner = make_view_planner(s);
  ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.region = kRegion;
  std::vector<ScoredView> scored;
  req.on_scored = [&](const ScoredView& v) { scored.push_back(v); };
  planner->next(req);
  ASSERT_GT(scored.size(), 20u);

  CameraIntrinsics K;
  ViewFeatures features(K, s.params, ViewFeatureParams{});
  const Pose T_now = synth::look_at(Vec3(0.1, 0.0, 1.0), kFruit);
  features.begin_round(map, index, kRegion, T_now);
  ASSERT_EQ(features.fruits().size(), 1u);
  ViewEvaluator eval(index, K, s.params.rays);
  const auto uvc = make_gain("uvc", s.params.gain), mi = make_gain("mi", s.params.gain);
  std::vector<float> f;
  int positive = 0;
  for (const ScoredView& v : scored) {
    features.compute(v.candidate.T_world_camera, v.candidate.target, &f);
    ASSERT_EQ(f.size(), view_feature_names().size());
    EXPECT_NEAR(f[feature("shape_seen")], v.score.gain, 1e-3 * (1.0 + v.score.gain));
    positive += v.score.gain > 0.0;
    EXPECT_EQ(f[feature("uvc@ours")],
              float(eval.evaluate(v.candidate.T_world_camera, v.candidate.target, *uvc, ray_set("ours"), 0).gain));
    EXPECT_EQ(f[feature("mi@sparse")],
              float(eval.evaluate(v.candidate.T_world_camera, v.candidate.target, *mi, ray_set("sparse"), 0).gain));
    EXPECT_GE(f[feature("shape_seen_fruit_prob")], f[feature("shape_seen")] - 1e-3f);
  }
  EXPECT_GT(positive, 5);
  // The camera now has not moved; half the fruit is seen.
  features.compute(T_now, kFruit, &f);
  EXPECT_NEAR(f[feature("move_m")], 0.0, 1e-6);
  EXPECT_NEAR(f[feature("move_deg")], 0.0, 1e-3);
  EXPECT_GT(f[feature("fruit_seen")], 0.2);
  EXPECT_LT(f[feature("fruit_seen")], 0.8);
  EXPECT_EQ(f[feature("fit_ok")], 1.f);
  EXPECT_GT(f[feature("fruit_label_consistency")], 0.9);
}

// Looking at the unseen back (from +x) is on the fruit's unseen side, the front (from -x) is not;
// behind the leaf, more of the predicted surface in view is blocked than from its mirror.
TEST(ViewFeatures, TellTheUnseenSideAndTheLeafThatBlocksIt) {
  const mapping::SemanticOcTree map = front_map();
  VoxelIndex index(map);
  CameraIntrinsics K;
  ViewFeatures features(K, NbvParams{}, ViewFeatureParams{});
  features.begin_round(map, index, kRegion, synth::look_at(Vec3(0.1, 0.0, 1.0), kFruit));
  const Vec3 centre = features.fruits().at(0).shape.centre;
  std::vector<float> back, front, leaf_side, clear_side;
  auto at = [&](double azimuth_deg, std::vector<float>* f) {
    const double a = azimuth_deg * M_PI / 180.0;
    features.compute(synth::look_at(centre + 0.4 * Vec3(std::cos(a), std::sin(a), 0.0), centre), centre, f);
  };
  at(0, &back);
  at(180, &front);
  at(40, &leaf_side);
  at(-40, &clear_side);
  EXPECT_GT(back[feature("unseen_side_cos")], 0.5);
  EXPECT_LT(front[feature("unseen_side_cos")], -0.5);
  EXPECT_GT(back[feature("shape_seen")], 4.0 * front[feature("shape_seen")]);
  EXPECT_GT(leaf_side[feature("ours_rays_blocked")] + leaf_side[feature("shape_blocked")],
            clear_side[feature("ours_rays_blocked")] + clear_side[feature("shape_blocked")]);
  EXPECT_NEAR(back[feature("target_distance_m")], 0.4, 1e-6);
  EXPECT_NEAR(back[feature("target_axis_deg")], 0.0, 0.1);
}

}  // namespace

namespace {

// The loop's own test of a predicted point (ViewFeatures::compute): in the depth range and in
// the image.
bool point_in_view(const CameraIntrinsics& K, const Pose& T, const Vec3& p) {
  const Vec3 c = T.inverse() * p;
  if (c.z() < K.min_range_m || c.z() > K.max_range_m) return false;
  double u = 0, v = 0;
  return K.project(c, &u, &v) && u >= 0.0 && v >= 0.0 && u < K.width_px && v < K.height_px;
}

}  // namespace

// The frustum prefilter (sphere_out_of_view) against the loop's own test on every point: on
// random camera poses and fruit-sized spheres, a sphere it calls out of view holds no point the
// loop would count (points inside and on the sphere, closest to the image borders and depth
// limits too); and it is not vacuous: it rejects most spheres out of view, keeps those in view.
TEST(ViewFeatures, FrustumPrefilterSkipsOnlyPointsTheLoopSkips) {
  CameraIntrinsics K;
  Rng rng(47);
  int rejected = 0, any_in_view = 0, in_view_rejected = 0, outside_kept = 0, outside = 0;
  for (int i = 0; i < 4000; ++i) {
    Pose T = Pose::Identity();
    T.linear() = (Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), Vec3::UnitZ()) *
                  Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), Vec3::UnitY()) *
                  Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), Vec3::UnitX()))
                     .toRotationMatrix();
    T.translation() = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 2));
    const double radius = rng.uniform(0.0, 0.08);
    // Centres around the camera, many near the frustum's planes and depth limits.
    const Vec3 centre = T * Vec3(rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8), rng.uniform(-0.2, 1.3));
    const bool out = sphere_out_of_view(K, T, centre, radius);
    rejected += out;
    bool in_view = false;
    for (int k = 0; k < 400; ++k) {
      Vec3 d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      if (d.norm() < 1e-9) continue;
      d *= (k % 2 == 0 ? radius : rng.uniform(0.0, radius)) / d.norm();  // on the sphere, and inside it
      const bool seen = point_in_view(K, T, centre + d);
      in_view = in_view || seen;
      if (out) {
        ASSERT_FALSE(seen) << "pose " << i << " point " << k;
      }
    }
    any_in_view += in_view;
    in_view_rejected += in_view && out;
    const bool centre_out = !point_in_view(K, T, centre);
    const Vec3 c = T.inverse() * centre;
    if (centre_out && (c.z() > K.max_range_m + radius + 0.01 || c.z() < K.min_range_m - radius - 0.01)) {
      ++outside;
      outside_kept += !out;
    }
  }
  EXPECT_EQ(in_view_rejected, 0);
  EXPECT_GT(any_in_view, 200);
  EXPECT_GT(rejected, 2000);
  EXPECT_EQ(outside_kept, 0) << "of " << outside << " spheres clear of the depth range";
}

// The ray sets' features kept between rounds are the ones computed afresh, bit for bit, while the
// map changes on one side of the scene between rounds (views whose rays cross it are cast again,
// the others kept) and once the index is rebuilt (everything cast again).
TEST(ViewFeatures, KeptRayFeaturesEqualFreshOnesAsTheMapChanges) {
  mapping::SemanticOcTree map = front_map();
  VoxelIndex index(map);
  const NbvParams nbv;
  CameraIntrinsics K;
  ViewFeatures kept(K, nbv, ViewFeatureParams{});
  // Views of the fruit from around it.
  Rng rng(12);
  std::vector<std::pair<Pose, Vec3>> views;
  for (int i = 0; i < 60; ++i) {
    const double az = rng.uniform(-M_PI, M_PI), el = rng.uniform(-0.6, 0.6), r = rng.uniform(0.25, 0.45);
    const Vec3 target = kFruit + Vec3(rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02));
    const Vec3 eye = kFruit + r * Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    views.emplace_back(synth::look_at(eye, target), target);
  }
  const Pose T_now = synth::look_at(Vec3(0.1, 0.0, 1.0), kFruit);
  std::size_t cast_before = 0;
  for (int round = 0; round < 6; ++round) {
    ViewFeatures fresh(K, nbv, ViewFeatureParams{});
    kept.begin_round(map, index, kRegion, T_now);
    fresh.begin_round(map, index, kRegion, T_now);
    std::vector<float> a, b;
    for (std::size_t v = 0; v < views.size(); ++v) {
      kept.compute(views[v].first, views[v].second, &a);
      fresh.compute(views[v].first, views[v].second, &b);
      ASSERT_EQ(a.size(), b.size());
      ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << "round " << round << " view " << v;
    }
    if (round == 0) {
      EXPECT_EQ(kept.rays_cast(), views.size());
    } else if (round != 4) {
      EXPECT_GT(kept.rays_cast(), cast_before) << "round " << round;                  // some cast again
      EXPECT_LT(kept.rays_cast(), cast_before + views.size()) << "round " << round;   // some kept
    } else {
      EXPECT_EQ(kept.rays_cast(), cast_before + views.size());  // after the rebuild
    }
    cast_before = kept.rays_cast();
    // Voxels changed on the +y side, beyond the leaf: views from -y do not reach them (round 3:
    // the index is rebuilt instead).
    if (round == 3) {
      index.rebuild(map);
      continue;
    }
    std::vector<mapping::VoxelUpdate> u;
    for (int i = 0; i < 200; ++i) {
      octomap::OcTreeKey k;
      ASSERT_TRUE(map.key_of(kFruit + Vec3(rng.uniform(-0.1, 0.1), rng.uniform(0.12, 0.22), rng.uniform(-0.1, 0.1)), &k));
      const double r = rng.uniform(0.0, 1.0);
      u.push_back({mapping::morton_code(k), r < 0.5 ? mapping::VoxelUpdate::kFree : std::uint8_t(r < 0.8 ? 2 : 1)});
    }
    std::sort(u.begin(), u.end(), [](const auto& x, const auto& y) { return x.code < y.code; });
    u.erase(std::unique(u.begin(), u.end(), [](const auto& x, const auto& y) { return x.code == y.code; }), u.end());
    const std::uint64_t before = map.revision();
    map.apply_sorted_updates(u);
    ASSERT_TRUE(index.apply_updates(map, before, u));
  }
  EXPECT_GT(kept.rays_kept(), views.size() / 2);
}

// Calls f(key, voxel centre, distance to c) for every voxel of the box c ± 2r (fruits built
// voxel by voxel).
template <class F>
void for_each_voxel_around(const mapping::SemanticOcTree& map, const Vec3& c, double r, F&& f) {
  octomap::OcTreeKey k0, k1;
  ASSERT_TRUE(map.key_of(c - Vec3::Constant(2 * r), &k0) && map.key_of(c + Vec3::Constant(2 * r), &k1));
  for (int x = k0[0]; x <= k1[0]; ++x)
    for (int y = k0[1]; y <= k1[1]; ++y)
      for (int z = k0[2]; z <= k1[2]; ++z) {
        const octomap::OcTreeKey k{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
        const octomap::point3d q = map.keyToCoord(k);
        const Vec3 v(q.x(), q.y(), q.z());
        f(k, v, (v - c).norm());
      }
}

// The evidence features (fruit_logodds_mean .. fruit_unseen_share) on fruits built voxel by
// voxel: the front halves of spherical shells of fruit voxels, the lower quarter hit 3 times,
// the upper 5 times.
// Their log-odds are the hits (psi = 1 a hit, first hit included), the strongest other class's
// is the "others" bucket (phi = -0.1 a hit); inside a fit never observed the voxels are unknown,
// observed free they are free, a leaf voxel inside counts as another class; two fruits 0.14 m
// apart are each other's neighbour, one 0.5 m away is nobody's; the fruits' unseen shares sum to one.
TEST(ViewFeatures, ReadAFruitsEvidenceFromItsVoxelsAndItsFit) {
  mapping::SemanticMapParams p;
  p.threads = 1;
  const double r = 0.03;
  const Vec3 a(0.5, 0.0, 1.0), b = a + Vec3(0.0, 0.14, 0.0), far = a + Vec3(0.0, -0.5, 0.0);
  const auto build = [&](bool interior_free, bool leaf_inside) {
    mapping::SemanticOcTree map(p, SemanticClasses{});
    const int fruit = map.classes().target_index(), leaf = 1;
    const double res = map.getResolution();
    for (const Vec3& c : {a, b, far}) {
      for_each_voxel_around(map, c, r, [&](const octomap::OcTreeKey& k, const Vec3& v, double d) {
        if (std::abs(d - r) <= res / 2 && v.x() <= c.x()) {  // the front half: the back unseen
          for (int h = 0; h < (v.z() < c.z() ? 3 : 5); ++h) map.update_hit(k, fruit);
        } else if (d < r - res / 2 && interior_free) {
          map.update_free(k);
        }
      });
      if (leaf_inside) {
        octomap::OcTreeKey k;
        EXPECT_TRUE(map.key_of(c, &k));
        map.update_hit(k, leaf);
      }
    }
    return map;
  };
  const Eigen::AlignedBox3d region(Vec3(0.2, -0.8, 0.6), Vec3(0.8, 0.4, 1.4));
  CameraIntrinsics K;
  const auto evidence = [&](const mapping::SemanticOcTree& map) {
    VoxelIndex index(map);
    ViewFeatures features(K, NbvParams{}, ViewFeatureParams{});
    features.begin_round(map, index, region, synth::look_at(Vec3(0.1, 0.0, 1.0), a));
    EXPECT_EQ(features.fruits().size(), 3u);
    std::vector<std::vector<float>> out;
    for (const Vec3& c : {a, b, far}) {
      out.emplace_back();
      features.compute(synth::look_at(c - Vec3(0.4, 0.0, 0.0), c), c, &out.back());
    }
    return out;
  };
  const auto unknown = evidence(build(false, false));
  const auto known = evidence(build(true, false));
  const auto leafy = evidence(build(true, true));
  for (const auto& f : unknown) {
    EXPECT_GT(f[feature("fruit_logodds_mean")], 3.5f);
    EXPECT_LT(f[feature("fruit_logodds_mean")], 4.5f);
    EXPECT_FLOAT_EQ(f[feature("fruit_logodds_min")], 3.f);
    EXPECT_GT(f[feature("fruit_other_logodds")], -0.5f - 1e-5f);
    EXPECT_LT(f[feature("fruit_other_logodds")], -0.3f + 1e-5f);
    EXPECT_GT(f[feature("fruit_inside_unknown")], 0.3f);
    EXPECT_EQ(f[feature("fruit_inside_free")], 0.f);
    EXPECT_EQ(f[feature("fruit_inside_other")], 0.f);
    EXPECT_GT(f[feature("fruit_around_unknown")], 0.5f);
    EXPECT_GE(f[feature("fruit_elongation")], 1.f);
    EXPECT_GT(f[feature("fruit_size_ratio")], 0.f);
  }
  EXPECT_EQ(unknown[0][feature("fruit_neighbours")], 1.f);
  EXPECT_EQ(unknown[1][feature("fruit_neighbours")], 1.f);
  EXPECT_EQ(unknown[2][feature("fruit_neighbours")], 0.f);
  float shares = 0.f;
  for (const auto& f : unknown) shares += f[feature("fruit_unseen_share")];
  EXPECT_NEAR(shares, 1.f, 1e-5f);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(known[i][feature("fruit_inside_unknown")] + known[i][feature("fruit_inside_free")],
                unknown[i][feature("fruit_inside_unknown")], 1e-5f);  // free where unknown was
    EXPECT_GT(known[i][feature("fruit_inside_free")], 0.1f);
    EXPECT_EQ(known[i][feature("fruit_inside_other")], 0.f);
    EXPECT_GT(leafy[i][feature("fruit_inside_other")], 0.f);
    EXPECT_EQ(unknown[i][feature("fruit_logodds_mean")], known[i][feature("fruit_logodds_mean")]);
  }
}

// fruit_min_logodds: a fruit whose voxels were each hit once as fruit (log-odds 1) is no fruit
// at the clustering's 1 (a voxel needs log-odds above it: two hits), and is one at 0; a fruit hit
// twice is one at both.
TEST(ViewFeatures, AFruitHitOnceIsAFruitOnlyBelowTheClusteringsThreshold) {
  mapping::SemanticMapParams p;
  p.threads = 1;
  const double r = 0.03;
  const Vec3 once(0.5, 0.0, 1.0), twice = once + Vec3(0.0, 0.3, 0.0);
  mapping::SemanticOcTree map(p, SemanticClasses{});
  const int fruit = map.classes().target_index();
  const double res = map.getResolution();
  for (const auto& [c, hits] : {std::pair<Vec3, int>{once, 1}, std::pair<Vec3, int>{twice, 2}}) {
    const Vec3 centre = c;
    const int n = hits;
    for_each_voxel_around(map, centre, r, [&](const octomap::OcTreeKey& k, const Vec3& v, double d) {
      if (std::abs(d - r) <= res / 2 && v.x() <= centre.x())
        for (int h = 0; h < n; ++h) map.update_hit(k, fruit);
    });
  }
  const Eigen::AlignedBox3d region(Vec3(0.2, -0.4, 0.6), Vec3(0.8, 0.6, 1.4));
  const auto fruits = [&](double threshold) {
    VoxelIndex index(map);
    ViewFeatureParams fp;
    fp.fruit_min_logodds = threshold;
    ViewFeatures features(CameraIntrinsics{}, NbvParams{}, fp);
    features.begin_round(map, index, region, synth::look_at(Vec3(0.1, 0.15, 1.0), once));
    std::vector<double> y;
    for (const FittedFruit& f : features.fruits()) y.push_back(f.cluster.centroid.y());
    std::sort(y.begin(), y.end());
    return y;
  };
  EXPECT_EQ(NbvParams{}.cluster.min_logodds, 1.0);
  const std::vector<double> at_one = fruits(1.0), at_zero = fruits(0.0);
  ASSERT_EQ(at_one.size(), 1u);
  EXPECT_NEAR(at_one[0], twice.y(), 0.02);
  ASSERT_EQ(at_zero.size(), 2u);
  EXPECT_NEAR(at_zero[0], once.y(), 0.02);
  EXPECT_NEAR(at_zero[1], twice.y(), 0.02);
}
