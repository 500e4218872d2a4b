// The shape fit (mapping/shape_fit.h) on analytic partial surfaces with fixed seeds: the half of
// an ellipsoid and of a superellipsoid (a blocky pepper) seen from one side, as exact points, as
// noisy points and as the centres of the 1.5 cm voxels a map holds. Tolerances are stated per
// test; the voxel-only figures (the points' centroid) are checked to be worse, so the fit earns
// its keep.

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "canopy/common/random.h"
#include "canopy/mapping/shape_fit.h"

using namespace canopy;
using namespace canopy::mapping;

namespace {

const Vec3 kCentre(0.5, 0.2, 1.0);

double sgn_pow(double v, double e) { return (v < 0 ? -1.0 : 1.0) * std::pow(std::abs(v), e); }

// Points of the surface (|x/a|^(2/e2) + |y/b|^(2/e2))^(e2/e1) + |z/c|^(2/e1) = 1 (e1 = e2 = 1:
// an ellipsoid) facing +x (the half a camera on the +x side sees), by the parametric form.
std::vector<Vec3> half_surface(const Vec3& axes, double e1, double e2, int n, double noise_m, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) {
    const double eta = rng.uniform(-M_PI / 2, M_PI / 2), omega = rng.uniform(-M_PI / 2, M_PI / 2);
    const double ce = sgn_pow(std::cos(eta), e1), se = sgn_pow(std::sin(eta), e1);
    Vec3 p(axes.x() * ce * sgn_pow(std::cos(omega), e2), axes.y() * ce * sgn_pow(std::sin(omega), e2), axes.z() * se);
    p += noise_m * Vec3(rng.normal(), rng.normal(), rng.normal());
    out.push_back(kCentre + p);
  }
  return out;
}

// The centres of the voxels of edge `res` that the points fall in (each once).
std::vector<Vec3> voxelise(const std::vector<Vec3>& pts, double res) {
  std::set<std::tuple<long, long, long>> cells;
  for (const Vec3& p : pts)
    cells.insert({std::lround(std::floor(p.x() / res)), std::lround(std::floor(p.y() / res)), std::lround(std::floor(p.z() / res))});
  std::vector<Vec3> out;
  for (const auto& [x, y, z] : cells) out.push_back(res * Vec3(double(x) + 0.5, double(y) + 0.5, double(z) + 0.5));
  return out;
}

Vec3 centroid(const std::vector<Vec3>& pts) {
  Vec3 m = Vec3::Zero();
  for (const Vec3& p : pts) m += p;
  return m / double(pts.size());
}

}  // namespace

// Half an ellipsoid, 2 mm noise: centre within 3 mm, semi-axes within 4 mm. The axes differ from
// the prior (0.035, 0.035, 0.055) by up to 10 mm: the data, not the prior, sets them.
TEST(ShapeFit, HalfEllipsoidRecoversCentreAndAxes) {
  const Vec3 axes(0.042, 0.042, 0.05);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto pts = half_surface(axes, 1.0, 1.0, 400, 0.002, seed);
    const FruitShape s = fit_fruit_shape(pts, ShapeFitParams{});
    ASSERT_TRUE(s.ok);
    EXPECT_LT((s.centre - kCentre).norm(), 0.003) << "seed " << seed;
    EXPECT_LT((s.semi_axes - axes).cwiseAbs().maxCoeff(), 0.004) << "seed " << seed << ": " << s.semi_axes.transpose();
    EXPECT_LT(s.rms_m, 0.004);
    // The voxel-only centre (the centroid of the seen half) lies ~a/2 in front of the true one.
    EXPECT_GT((centroid(pts) - kCentre).norm(), 0.015);
  }
}

// The whole surface without noise: exact to 0.1 mm; its predicted surface lies on it.
TEST(ShapeFit, WholeEllipsoidIsExactAndItsSurfaceLiesOnIt) {
  const Vec3 axes(0.04, 0.04, 0.06);
  FruitShape truth;
  truth.centre = kCentre;
  truth.semi_axes = axes;
  const std::vector<Vec3> pts = shape_surface(truth, 300);
  for (const Vec3& p : pts) EXPECT_NEAR(truth.distance(p), 0.0, 1e-12);
  const FruitShape s = fit_fruit_shape(pts, ShapeFitParams{});
  ASSERT_TRUE(s.ok);
  EXPECT_LT((s.centre - kCentre).norm(), 1e-4);
  EXPECT_LT((s.semi_axes - axes).cwiseAbs().maxCoeff(), 1e-3);  // the prior pulls a little
  EXPECT_NEAR(s.volume_m3(), 4.0 / 3.0 * M_PI * 0.04 * 0.04 * 0.06, 0.01 * 4e-4);
  // Spaced samples: about area / spacing^2 of them.
  const auto spaced = shape_surface_spaced(truth, 0.01);
  EXPECT_GT(spaced.size(), 150u);
  EXPECT_LT(spaced.size(), 350u);
}

// Half a blocky superellipsoid (e1 = 0.6, e2 = 0.8) as a map holds it (1.5 cm voxel centres):
// centre within 8 mm (the voxel-only centroid is over 15 mm off), volume within 25 %.
TEST(ShapeFit, HalfSuperellipsoidAsVoxelsRecoversCentreAndVolume) {
  const Vec3 axes(0.04, 0.04, 0.05);
  // Volume of a superellipsoid: 2 a b c e1 e2 B(e1/2 + 1, e1) B(e2/2, e2/2).
  auto beta = [](double x, double y) { return std::tgamma(x) * std::tgamma(y) / std::tgamma(x + y); };
  const double e1 = 0.6, e2 = 0.8;
  const double volume = 2.0 * axes.prod() * e1 * e2 * beta(e1 / 2 + 1, e1) * beta(e2 / 2, e2 / 2);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto pts = voxelise(half_surface(axes, e1, e2, 5000, 0.0, seed), 0.015);
    ASSERT_GE(pts.size(), 20u);
    const FruitShape s = fit_fruit_shape(pts, ShapeFitParams{});
    ASSERT_TRUE(s.ok);
    EXPECT_LT((s.centre - kCentre).norm(), 0.008) << "seed " << seed << ": " << s.centre.transpose();
    EXPECT_LT(std::abs(s.volume_m3() - volume) / volume, 0.25) << s.semi_axes.transpose();
    EXPECT_GT((centroid(pts) - kCentre).norm(), 0.015);
  }
}

// Too few points: no fit, the prior's ellipsoid at the centroid.
TEST(ShapeFit, TooFewPointsGiveThePrior) {
  const std::vector<Vec3> pts = {kCentre, kCentre + Vec3(0.01, 0, 0), kCentre + Vec3(0, 0.01, 0)};
  const FruitShape s = fit_fruit_shape(pts, ShapeFitParams{});
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.semi_axes, Vec3(0.035, 0.035, 0.055));
  EXPECT_FALSE(fit_fruit_shape({}, ShapeFitParams{}).ok);
}
