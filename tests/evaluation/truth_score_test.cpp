// The truth scorer (evaluation/truth_score.h) on an analytic render: a camera looking along +z
// at a wall at a known depth. Points in front of the wall are seen, points behind it are not,
// points outside the image or depth range are not even in the frustum; branch and bound
// returns what scoring every view returns, with fewer renders.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "canopy/common/random.h"
#include "canopy/evaluation/truth_score.h"

namespace canopy::evaluation {
namespace {

constexpr double kWallZ = 0.6;  // the wall: the plane z = 0.6 m (world), facing cameras at z = 0

// The planar depth of the wall z = kWallZ from camera pose T, pixel by pixel (0 where the ray
// misses it or it lies behind the camera).
TruthDepthRender wall_render(const CameraIntrinsics& K) {
  return [K](const Pose& T) {
    Image<float> depth(K.width_px, K.height_px, 0.f);
    for (int v = 0; v < K.height_px; ++v)
      for (int u = 0; u < K.width_px; ++u) {
        const Vec3 d_cam = K.ray_direction(u + 0.5, v + 0.5);  // z = 1
        const Vec3 d_world = T.linear() * d_cam;
        if (!(d_world.z() > 1e-9)) continue;
        const double s = (kWallZ - T.translation().z()) / d_world.z();  // planar depth = s (d_cam.z = 1)
        if (s > 0.0) depth.at(u, v) = float(s);
      }
    return depth;
  };
}

// A camera at (x, y, 0) looking along +z.
Pose camera_at(double x, double y) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(x, y, 0.0);
  return T;
}

TEST(TruthScore, PointsBeforeTheWallAreSeenAndPointsBehindItAreNot) {
  const CameraIntrinsics K = truth_render_intrinsics(CameraIntrinsics{}, 4);
  EXPECT_EQ(K.width_px, CameraIntrinsics{}.width_px / 4);
  EXPECT_EQ(K.depth_noise_k, 0.0);
  TruthViewScorer scorer(K, 0.005, wall_render(K));
  std::vector<UncoveredPoint> pts;
  for (int i = -5; i <= 5; ++i) {
    pts.push_back({Vec3(0.02 * i, 0.0, 0.4), 1});      // in front of the wall: seen
    pts.push_back({Vec3(0.02 * i, 0.01, kWallZ), 1});  // on the wall: seen (within the tolerance)
    pts.push_back({Vec3(0.02 * i, 0.0, 0.8), 2});      // behind the wall: in the frustum, not seen
  }
  scorer.set_points(pts);
  const Pose T = camera_at(0.0, 0.0);
  EXPECT_EQ(scorer.in_frustum(T), pts.size());
  EXPECT_EQ(scorer.visible(T), 22u);
  EXPECT_EQ(scorer.renders(), 1u);
  // Far to the side: nothing in the frustum, nothing rendered.
  EXPECT_EQ(scorer.in_frustum(camera_at(5.0, 0.0)), 0u);
  EXPECT_EQ(scorer.visible(camera_at(5.0, 0.0)), 0u);
  EXPECT_EQ(scorer.renders(), 1u);
  // Beyond the depth range: not in the frustum.
  scorer.set_points({{Vec3(0.0, 0.0, K.max_range_m + 0.1), 3}});
  EXPECT_EQ(scorer.in_frustum(T), 0u);
}

TEST(TruthScore, BranchAndBoundEqualsScoringEveryView) {
  const CameraIntrinsics K = truth_render_intrinsics(CameraIntrinsics{}, 8);
  TruthViewScorer scorer(K, 0.005, wall_render(K));
  Rng rng(7);
  std::vector<UncoveredPoint> pts;
  for (int i = 0; i < 400; ++i)
    pts.push_back({Vec3(rng.uniform(-0.6, 0.6), rng.uniform(-0.4, 0.4), rng.uniform(0.3, 0.9)), 1});
  scorer.set_points(pts);
  std::vector<Pose> views;
  for (int i = 0; i < 30; ++i) views.push_back(camera_at(rng.uniform(-1.5, 1.5), rng.uniform(-1.0, 1.0)));
  std::vector<std::pair<std::size_t, std::size_t>> every;  // (score, view), best first, ties by view
  for (std::size_t i = 0; i < views.size(); ++i) every.push_back({scorer.visible(views[i]), i});
  std::stable_sort(every.begin(), every.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const std::size_t before = scorer.renders();
  std::vector<Pose> copy = views;
  const std::vector<TruthScore> best = best_truth_views(scorer, &copy, 4);
  ASSERT_EQ(best.size(), 4u);
  for (std::size_t k = 0; k < best.size(); ++k) {
    EXPECT_EQ(best[k].view, every[k].second) << k;
    EXPECT_EQ(best[k].score, every[k].first) << k;
    EXPECT_GE(best[k].bound, best[k].score);
  }
  EXPECT_LT(scorer.renders() - before, views.size());
  // accept() may refuse a view: the next best takes its place.
  copy = views;
  const std::vector<TruthScore> refused =
      best_truth_views(scorer, &copy, 1, [&](std::size_t i, Pose*) { return i != every[0].second; });
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].view, every[1].second);
}

// cache_views: each pose is rendered once; later rounds with other point subsets (some points
// covered, some uncovered again) count exactly what a scorer without the cache counts, and
// the frustum bounds best_truth_views hands back equal in_frustum of the final poses.
TEST(TruthScore, KeptViewsCountWhatRenderingAgainCounts) {
  const CameraIntrinsics K = truth_render_intrinsics(CameraIntrinsics{}, 8);
  TruthViewScorer cached(K, 0.005, wall_render(K)), fresh(K, 0.005, wall_render(K));
  Rng rng(11);
  std::vector<Vec3> universe;
  for (int i = 0; i < 600; ++i)
    universe.push_back(Vec3(rng.uniform(-0.6, 0.6), rng.uniform(-0.4, 0.4), rng.uniform(0.3, 0.9)));
  cached.cache_views(universe);
  std::vector<Pose> views;
  for (int i = 0; i < 12; ++i) views.push_back(camera_at(rng.uniform(-1.0, 1.0), rng.uniform(-0.7, 0.7)));
  for (int round = 0; round < 6; ++round) {
    std::vector<UncoveredPoint> pts;
    for (std::size_t i = 0; i < universe.size(); ++i)
      if (rng.uniform(0.0, 1.0) < 0.7 - 0.1 * round) pts.push_back({universe[i], 1, i});
    cached.set_points(pts);
    fresh.set_points(pts);
    for (const Pose& T : views) {
      EXPECT_EQ(cached.visible(T), fresh.visible(T)) << round;
      EXPECT_EQ(cached.in_frustum(T), fresh.in_frustum(T)) << round;
    }
    std::vector<Pose> a = views, b = views;
    std::vector<std::size_t> bounds;
    const std::vector<TruthScore> best_a = best_truth_views(cached, &a, 3, nullptr, &bounds);
    const std::vector<TruthScore> best_b = best_truth_views(fresh, &b, 3);
    ASSERT_EQ(best_a.size(), best_b.size());
    for (std::size_t k = 0; k < best_a.size(); ++k) {
      EXPECT_EQ(best_a[k].view, best_b[k].view);
      EXPECT_EQ(best_a[k].score, best_b[k].score);
    }
    ASSERT_EQ(bounds.size(), views.size());
    for (std::size_t i = 0; i < views.size(); ++i) EXPECT_EQ(bounds[i], fresh.in_frustum(views[i]));
  }
  // Every pose seeing a point was rendered once (the first round), then only counted.
  EXPECT_LE(cached.renders(), views.size());
  EXPECT_GT(cached.reused(), 0u);
  EXPECT_GT(fresh.renders(), 2 * views.size());
  // A changed scene: forget the views, the next call renders again.
  const std::size_t before = cached.renders();
  cached.forget_views();
  cached.visible(views[0]);
  EXPECT_EQ(cached.renders(), before + (cached.in_frustum(views[0]) > 0 ? 1u : 0u));
}

// in_frustum tests balls of points and goes point by point only where a ball straddles the
// frustum's boundary: it counts what testing every point counts, also for turned cameras and
// points packed along the boundary.
TEST(TruthScore, FrustumCountEqualsTestingEveryPoint) {
  const CameraIntrinsics K = truth_render_intrinsics(CameraIntrinsics{}, 4);
  Rng rng(5);
  std::vector<UncoveredPoint> pts;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 centre(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-0.5, 2.5));
    const int n = 1 + int(rng.uniform(0.0, 40.0));  // fruit-like clumps of consecutive points
    for (int k = 0; k < n && pts.size() < 6000; ++k)
      pts.push_back({centre + 0.03 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)), 1});
  }
  // Points on the image's left edge and the near limit of a camera at the origin.
  for (int k = 0; k < 64; ++k) {
    const double z = 0.5 + 0.01 * k;
    pts.push_back({Vec3((0.0 - K.cx_px) * z / K.fx_px, 0.0, z), 2});
    pts.push_back({Vec3(0.0, 0.0, K.min_range_m), 2});
  }
  TruthViewScorer scorer(K, 0.005, wall_render(K));
  scorer.set_points(pts);
  for (int i = 0; i < 40; ++i) {
    Pose T = Pose::Identity();
    if (i > 0) {
      T.linear() = (Eigen::AngleAxisd(rng.uniform(-0.6, 0.6), Vec3::UnitX()) *
                    Eigen::AngleAxisd(rng.uniform(-0.6, 0.6), Vec3::UnitY()))
                       .toRotationMatrix();
      T.translation() = Vec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.2));
    }
    const Pose T_inv = T.inverse();
    std::size_t every = 0;
    for (const UncoveredPoint& p : pts) {
      const Vec3 c = T_inv * p.position;
      double u = 0, v = 0;
      every += c.z() >= K.min_range_m && c.z() <= K.max_range_m && K.project(c, &u, &v) && K.in_image(u, v);
    }
    EXPECT_EQ(scorer.in_frustum(T), every) << i;
  }
}

TEST(TruthScore, KeptViewsRefuseAPointNotOfTheUniverse) {
  const CameraIntrinsics K = truth_render_intrinsics(CameraIntrinsics{}, 8);
  TruthViewScorer scorer(K, 0.005, wall_render(K));
  scorer.cache_views({Vec3(0.0, 0.0, 0.4)});
  EXPECT_THROW(scorer.set_points({{Vec3(0.0, 0.0, 0.5), 1, 0}}), std::exception);
  EXPECT_THROW(scorer.set_points({{Vec3(0.0, 0.0, 0.4), 1, 3}}), std::exception);
}

}  // namespace
}  // namespace canopy::evaluation
