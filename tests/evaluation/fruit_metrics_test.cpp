// Fruit detection, shape and voxel precision on hand-built maps with known answers
// (fruit_metrics.h, docs/background/evaluation.md).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "canopy/evaluation/map_metrics.h"
#include "../mapping/synthetic.h"

using namespace canopy;
using namespace canopy::mapping;
using namespace canopy::evaluation;

namespace {

constexpr double kRes = 0.005;
constexpr double kR = 0.04;
constexpr int kFruit = 2;  // class index of "fruit" in the default classes

world::FruitTruth sphere_fruit(const Vec3& c, int id) {
  world::FruitTruth f = synth::sphere_truth(c, kR, 0.003, id);
  f.volume_m3 = 4.0 / 3.0 * M_PI * kR * kR * kR;
  return f;
}

SemanticOcTree make_fine_map() {
  SemanticMapParams p;
  p.resolution_m = kRes;
  return SemanticOcTree(p, SemanticClasses{});
}

// Marks every voxel whose centre lies within half a voxel of the sphere (c, r) as fruit
// (hit `hits` times); returns how many.
int paint_shell(SemanticOcTree& map, const Vec3& c, double r, int hits) {
  int n = 0;
  const int k = static_cast<int>(std::ceil((r + kRes) / kRes));
  octomap::OcTreeKey ck;
  EXPECT_TRUE(map.key_of(c, &ck));
  for (int z = -k; z <= k; ++z)
    for (int y = -k; y <= k; ++y)
      for (int x = -k; x <= k; ++x) {
        const octomap::OcTreeKey key(static_cast<octomap::key_type>(ck[0] + x), static_cast<octomap::key_type>(ck[1] + y),
                                     static_cast<octomap::key_type>(ck[2] + z));
        if (std::abs((map.center_of(key) - c).norm() - r) > kRes / 2) continue;
        for (int h = 0; h < hits; ++h) map.update_hit(key, kFruit);
        ++n;
      }
  return n;
}

}  // namespace

// Two fruits mapped whole, one never seen, and a 2 x 2 x 2 block of fruit voxels far from
// every fruit: 3 clusters, 2 matched of 3 fruits (precision = recall = F1 = 2/3), centres
// and ellipsoids right, 8 false voxels.
TEST(FruitMetrics, HandBuiltMapGivesTheKnownAnswers) {
  world::GroundTruth truth;
  const Vec3 a(0.3, 0.2, 0.8), b(0.5, 0.2, 0.8), c(0.7, 0.2, 0.8);
  truth.fruits = {sphere_fruit(a, 0), sphere_fruit(b, 1), sphere_fruit(c, 2)};
  SemanticOcTree map = make_fine_map();
  const int shell_a = paint_shell(map, a, kR, 3);
  const int shell_b = paint_shell(map, b, kR, 3);
  octomap::OcTreeKey k0;
  ASSERT_TRUE(map.key_of(Vec3(0.5, 0.5, 0.3), &k0));
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        for (int h = 0; h < 3; ++h)
          map.update_hit(octomap::OcTreeKey(static_cast<octomap::key_type>(k0[0] + x),
                                            static_cast<octomap::key_type>(k0[1] + y),
                                            static_cast<octomap::key_type>(k0[2] + z)),
                         kFruit);
  MetricsParams params;
  params.coverage_distance_m = kRes;
  const MapMetrics m = evaluate_map(map, truth, params);
  const FruitDetection& d = m.detection;
  ASSERT_EQ(d.clusters.size(), 3u);
  EXPECT_EQ(d.fruits, 3u);
  ASSERT_EQ(d.matches.size(), 2u);
  EXPECT_NEAR(d.precision, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(d.recall, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(d.f1, 2.0 / 3.0, 1e-12);
  for (const FruitMatch& x : d.matches) {
    const FruitCluster& cl = d.clusters[static_cast<std::size_t>(x.cluster)];
    EXPECT_TRUE(x.instance_id == 0 || x.instance_id == 1);
    EXPECT_EQ(cl.voxels, std::size_t(x.instance_id == 0 ? shell_a : shell_b));
    EXPECT_LT(x.centre_error_m, 0.25 * kRes);  // a whole shell: centroid at the centre up to the grid
    EXPECT_NEAR(cl.voxel_volume_m3, double(cl.voxels) * kRes * kRes * kRes, 1e-15);
    EXPECT_NEAR(cl.ellipsoid_volume_m3, x.true_volume_m3, 0.03 * x.true_volume_m3);
    EXPECT_NEAR(x.ellipsoid_volume_error, std::abs(cl.ellipsoid_volume_m3 - x.true_volume_m3) / x.true_volume_m3, 1e-12);
    EXPECT_LT(x.ellipsoid_volume_error, 0.03);
    // A shell one voxel thick holds far less than the solid fruit.
    EXPECT_GT(x.voxel_volume_error, 0.5);
  }
  EXPECT_NEAR(d.centre_error_m, 0.5 * (d.matches[0].centre_error_m + d.matches[1].centre_error_m), 1e-15);
  // The block is the only false fruit volume.
  EXPECT_EQ(m.voxel_precision.false_voxels, 8u);
  EXPECT_EQ(m.voxel_precision.true_voxels, std::size_t(shell_a + shell_b));
  EXPECT_NEAR(m.voxel_precision.precision, double(shell_a + shell_b) / double(shell_a + shell_b + 8), 1e-12);
  EXPECT_NEAR(m.voxel_precision.false_volume_m3, 8 * kRes * kRes * kRes, 1e-15);
  // Fruit-level completeness: two of three fruits are covered whole.
  EXPECT_NEAR(m.fruits_sc50, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(m.fruits_sc80, 2.0 / 3.0, 1e-12);
  const nlohmann::json j = m.to_json();
  EXPECT_EQ(j["detection"]["matched"], 2);
  EXPECT_EQ(j["fruit_voxel_precision"]["false_voxels"], 8);
}

// A shell shifted by 12 mm: matched (half the 80 mm fruit is 40 mm) with a 12 mm centre
// error, and its voxels more than a voxel's reach off the true surface are false.
TEST(FruitMetrics, ShiftedFruitHasItsCentreErrorAndFalseVoxels) {
  world::GroundTruth truth;
  const Vec3 a(0.3, 0.2, 0.8);
  truth.fruits = {sphere_fruit(a, 4)};
  SemanticOcTree map = make_fine_map();
  const Vec3 shift(0.012, 0.0, 0.0);
  paint_shell(map, a + shift, kR, 3);
  const MapMetrics m = evaluate_map(map, truth, MetricsParams{});
  ASSERT_EQ(m.detection.matches.size(), 1u);
  EXPECT_NEAR(m.detection.centre_error_m, 0.012, 0.25 * kRes);
  EXPECT_EQ(m.detection.f1, 1.0);
  EXPECT_GT(m.voxel_precision.false_voxels, 0u);
  EXPECT_GT(m.voxel_precision.true_voxels, 0u);
  // Shifted beyond the match distance: a false positive and a missed fruit.
  SemanticOcTree far = make_fine_map();
  paint_shell(far, a + Vec3(0.045, 0, 0), kR, 3);
  const MapMetrics f = evaluate_map(far, truth, MetricsParams{});
  EXPECT_EQ(f.detection.clusters.size(), 1u);
  EXPECT_EQ(f.detection.matches.size(), 0u);
  EXPECT_EQ(f.detection.f1, 0.0);
  EXPECT_TRUE(std::isnan(f.detection.centre_error_m));
  EXPECT_TRUE(f.to_json()["detection"]["centre_error_m"].is_null());
}

// The prototype rule's detection uses only voxels above its log-odds: one hit is not enough.
TEST(FruitMetrics, DetectionFollowsTheHeadlineRulesVoxels) {
  world::GroundTruth truth;
  const Vec3 a(0.3, 0.2, 0.8);
  truth.fruits = {sphere_fruit(a, 0)};
  SemanticOcTree map = make_fine_map();
  paint_shell(map, a, kR, 1);
  MetricsParams p;
  p.rule = EvaluationRule::kPrototype;
  EXPECT_EQ(evaluate_map(map, truth, p).detection.clusters.size(), 0u);
  p.rule = EvaluationRule::kPaper;
  EXPECT_EQ(evaluate_map(map, truth, p).detection.matches.size(), 1u);
}

TEST(FruitMetrics, ClustersAre26ConnectedComponents) {
  const auto at = [](int x, int y, int z) { return Vec3((x + 0.5) * kRes, (y + 0.5) * kRes, (z + 0.5) * kRes); };
  // Corner-touching voxels are one cluster; one empty voxel between separates.
  const std::vector<Vec3> pts = {at(0, 0, 0), at(1, 1, 1), at(2, 2, 2), at(4, 2, 2), at(10, 0, 0), at(-5, -5, -5)};
  const std::vector<FruitCluster> all = fruit_clusters(pts, kRes, 1);
  ASSERT_EQ(all.size(), 4u);
  // In the order of each cluster's first grid cell (x, then y, then z), whatever the input order.
  EXPECT_EQ(all[0].voxels, 1u);
  EXPECT_LT((all[0].centroid - at(-5, -5, -5)).norm(), 1e-12);
  EXPECT_EQ(all[1].voxels, 3u);
  EXPECT_LT((all[1].centroid - at(1, 1, 1)).norm(), 1e-12);
  EXPECT_EQ(all[2].voxels, 1u);
  EXPECT_LT((all[3].centroid - at(10, 0, 0)).norm(), 1e-12);
  // min_voxels drops the single voxels.
  EXPECT_EQ(fruit_clusters(pts, kRes, 2).size(), 1u);
  EXPECT_TRUE(fruit_clusters({}, kRes, 1).empty());
}

TEST(FruitMetrics, MatchingIsOneToOneClosestFirst) {
  world::GroundTruth truth;
  truth.fruits = {sphere_fruit(Vec3(0, 0, 1), 0), sphere_fruit(Vec3(0.05, 0, 1), 1)};  // 80 mm: match within 40 mm
  const auto cluster = [](double x) {
    FruitCluster c;
    c.centroid = Vec3(x, 0, 1);
    c.voxels = 10;
    return c;
  };
  // c1 (x = 0.03) is 20 mm from fruit 1 and 30 mm from fruit 0; c2 (x = 0.045) 5 mm from
  // fruit 1: closest first gives c2-fruit 1, then c1-fruit 0.
  FruitDetection d = detect_fruits({cluster(0.03), cluster(0.045)}, truth, 0.5);
  ASSERT_EQ(d.matches.size(), 2u);
  EXPECT_EQ(d.matches[0].cluster, 1);
  EXPECT_EQ(d.matches[0].instance_id, 1);
  EXPECT_EQ(d.matches[1].cluster, 0);
  EXPECT_EQ(d.matches[1].instance_id, 0);
  EXPECT_NEAR(d.centre_error_m, 0.5 * (0.005 + 0.03), 1e-12);
  // Two clusters on one fruit: one match, the other a false positive.
  truth.fruits.pop_back();
  d = detect_fruits({cluster(0.01), cluster(-0.002)}, truth, 0.5);
  ASSERT_EQ(d.matches.size(), 1u);
  EXPECT_EQ(d.matches[0].cluster, 1);
  EXPECT_EQ(d.precision, 0.5);
  EXPECT_EQ(d.recall, 1.0);
  EXPECT_NEAR(d.f1, 2.0 / 3.0, 1e-12);
  // Unripe fruits are not ground-truth fruits.
  truth.fruits[0].target = false;
  d = detect_fruits({cluster(0.0)}, truth, 0.5);
  EXPECT_EQ(d.fruits, 0u);
  EXPECT_EQ(d.matches.size(), 0u);
  EXPECT_EQ(d.recall, 0.0);
}

TEST(FruitMetrics, EllipsoidFitRecoversASphereAndAnEllipsoid) {
  const world::FruitTruth s = synth::sphere_truth(Vec3(1, 2, 3), 0.03, 0.001, 0);
  Vec3 axes;
  double v = 0.0;
  fit_ellipsoid(s.surface_points, &axes, &v);
  EXPECT_NEAR(axes.x(), 0.03, 3e-4);
  EXPECT_NEAR(axes.z(), 0.03, 3e-4);
  EXPECT_NEAR(v, 4.0 / 3.0 * M_PI * 0.027e-3, 0.02 * 4.0 / 3.0 * M_PI * 0.027e-3);
  // Stretched along z by 2: the long semi-axis doubles.
  std::vector<Vec3> stretched;
  for (const Vec3& p : s.surface_points) stretched.push_back(Vec3(p.x(), p.y(), 2 * p.z()));
  fit_ellipsoid(stretched, &axes, &v);
  EXPECT_NEAR(axes.x(), 0.06, 6e-4);
  EXPECT_NEAR(axes.z(), 0.03, 1e-3);
  fit_ellipsoid({Vec3::Zero()}, &axes, &v);
  EXPECT_EQ(v, 0.0);
}

// Shape completion per fruit (docs/shape.md): the seen half of a sphere of radius 4 cm as 1.5 cm
// voxel centres. The fitted centre lies within 5 mm of the fruit's (the voxels' centroid over
// 15 mm in front of it) and the fitted volume within 25 % (the voxel and moment-ellipsoid volumes
// see half a fruit); the per-fruit table has one row with both.
TEST(FruitMetrics, ShapeFitCompletesTheSeenHalf) {
  const Vec3 c(0.5, 0.2, 1.0);
  world::GroundTruth truth;
  truth.fruits.push_back(sphere_fruit(c, 7));
  truth.fruits[0].target = true;
  const double res = 0.015;
  std::set<std::int64_t> seen;
  std::vector<Vec3> half;
  for (const Vec3& p : truth.fruits[0].surface_points) {
    if (p.x() < c.x()) continue;
    const Vec3 v = ((p / res).array().floor() + 0.5).matrix() * res;
    if (seen.insert(fruit_cell(v, res)).second) half.push_back(v);
  }
  const std::vector<FruitCluster> clusters = fruit_clusters(half, res, 1);
  ASSERT_EQ(clusters.size(), 1u);
  const FruitDetection d = detect_fruits(clusters, truth, 0.5);
  ASSERT_EQ(d.matches.size(), 1u);
  EXPECT_EQ(d.shape_fits, 1u);
  EXPECT_GT(d.centre_error_m, 0.015);
  EXPECT_LT(d.shape_centre_error_m, 0.005);
  EXPECT_LT(d.shape_volume_error, 0.25);
  EXPECT_GT(d.ellipsoid_volume_error, d.shape_volume_error);
  const std::string csv = fruit_shapes_csv(d);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2);
  EXPECT_EQ(csv.rfind("instance_id,voxels,", 0), 0u);
  EXPECT_NE(csv.find("\n7,"), std::string::npos);
  EXPECT_NE(d.to_json()["shape_centre_error_m"], nullptr);
}
