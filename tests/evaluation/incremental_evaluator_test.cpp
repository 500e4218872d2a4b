// The incremental evaluation against the full one (evaluate_map, the reference): after every
// batch of voxel updates, every figure equal bit for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "canopy/evaluation/incremental_evaluator.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/perception/semantic_extractor.h"
#include "../mapping/synthetic.h"
#include "metrics_equal.h"

using namespace canopy;
using namespace canopy::mapping;
using namespace canopy::evaluation;

namespace {

world::GroundTruth two_fruits() {
  world::GroundTruth t;
  t.fruits.push_back(synth::sphere_truth(Vec3(0.4, 0.2, 1.0), 0.04, 0.003, 7));
  t.fruits.push_back(synth::sphere_truth(Vec3(0.55, 0.2, 1.05), 0.035, 0.003, 8));
  world::FruitTruth unripe = synth::sphere_truth(Vec3(0.3, 0.3, 0.9), 0.03, 0.003, 9);
  unripe.target = false;
  t.fruits.push_back(unripe);
  return t;
}

// Random hits (fruit, leaf) and pass-throughs (free_in_10 of 10 updates) in a box around the
// fruits: fruit voxels appear, change class, lose their prototype status and vanish again.
std::vector<VoxelUpdate> random_batch(const SemanticOcTree& map, std::mt19937& rng, int n, int free_in_10,
                                      double x_lo = 0.3, double x_hi = 0.65) {
  std::uniform_real_distribution<double> x(x_lo, x_hi), y(0.12, 0.28), z(0.92, 1.12);
  std::uniform_int_distribution<int> kind(0, 9);
  std::vector<VoxelUpdate> u;
  for (int i = 0; i < n; ++i) {
    octomap::OcTreeKey key;
    if (!map.key_of(Vec3(x(rng), y(rng), z(rng)), &key)) continue;
    VoxelUpdate v;
    v.code = morton_code(key);
    const int k = kind(rng);
    v.label = k < free_in_10 ? VoxelUpdate::kFree : k < 8 ? std::uint8_t(2) : std::uint8_t(1);
    u.push_back(v);
  }
  std::sort(u.begin(), u.end(), [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.code < b.code; });
  u.erase(std::unique(u.begin(), u.end(), [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.code == b.code; }),
          u.end());
  return u;
}

}  // namespace

TEST(IncrementalEvaluator, EqualsTheFullEvaluationAfterEveryRandomBatch) {
  const world::GroundTruth truth = two_fruits();
  for (EvaluationRule rule : {EvaluationRule::kPrototype, EvaluationRule::kPaper}) {
    MetricsParams params;
    params.rule = rule;
    SemanticOcTree map(SemanticMapParams{}, SemanticClasses{});
    IncrementalEvaluator inc(truth, params);
    std::mt19937 rng(11);
    std::size_t most_voxels = 0;
    bool lost_voxels = false;
    for (int batch = 0; batch < 60; ++batch) {
      const std::vector<VoxelUpdate> u = random_batch(map, rng, 400, batch < 40 ? 3 : 8);  // then mostly free
      map.apply_sorted_updates(u);
      const MapMetrics& got = inc.update(map, u);
      const MapMetrics want = evaluate_map(map, truth, params);
      SCOPED_TRACE("batch " + std::to_string(batch) + " rule " + to_string(rule));
      expect_same_metrics(got, want);
      EXPECT_TRUE(inc.follows(map));
      if (batch % 10 == 9) {  // a fresh evaluator scores the whole map at once: the same figures
        IncrementalEvaluator fresh(truth, params);
        EXPECT_FALSE(fresh.follows(map));
        expect_same_metrics(fresh.update(map, {}), want);
      }
      if (want.fruit_voxels_paper < most_voxels) lost_voxels = true;
      most_voxels = std::max(most_voxels, want.fruit_voxels_paper);
    }
    // The sequence exercised what it must: fruit voxels appeared, some vanished, points got covered.
    EXPECT_GT(most_voxels, 50u);
    EXPECT_TRUE(lost_voxels);
    EXPECT_GT(inc.metrics().paper.covered, 0u);
  }
}

// A row of fruits 4 m long scanned stretch by stretch, with a window pad of 5 cm: the k-d tree
// of true points is built again and again, holds a few fruits at a time, and every figure still
// equals the full evaluation's (and a fresh evaluator's first scoring of the whole map).
TEST(IncrementalEvaluator, AWindowOfPointsMovingAlongARowGivesTheFullEvaluation) {
  world::GroundTruth truth;
  for (int i = 0; i < 12; ++i)
    truth.fruits.push_back(synth::sphere_truth(Vec3(0.3 + 0.35 * i, 0.2, 1.0 + 0.02 * (i % 3)), 0.04, 0.003, 20 + i));
  std::size_t all_points = 0;
  for (const auto& f : truth.fruits) all_points += f.surface_points.size();
  MetricsParams params;
  SemanticOcTree map(SemanticMapParams{}, SemanticClasses{});
  IncrementalEvaluator inc(truth, params, 0.05);
  std::mt19937 rng(5);
  std::size_t most_held = 0;
  for (int batch = 0; batch < 32; ++batch) {
    // Forward along the row and back, each batch a 0.5 m stretch; the last ones clear voxels.
    const int step = batch < 16 ? batch : 31 - batch;
    const double x0 = 0.1 + 0.24 * step;
    const std::vector<VoxelUpdate> u = random_batch(map, rng, 500, batch < 24 ? 3 : 8, x0, x0 + 0.5);
    map.apply_sorted_updates(u);
    const MapMetrics& got = inc.update(map, u);
    SCOPED_TRACE("batch " + std::to_string(batch));
    expect_same_metrics(got, evaluate_map(map, truth, params));
    most_held = std::max(most_held, inc.window_points());
  }
  EXPECT_GT(inc.metrics().paper.covered, 0u);
  EXPECT_GE(inc.window_builds(), 10u);
  EXPECT_LT(most_held, all_points / 2);
  IncrementalEvaluator fresh(truth, params, 0.05);
  expect_same_metrics(fresh.update(map, {}), evaluate_map(map, truth, params));
}

TEST(IncrementalEvaluator, RescoresOnlyWhatAScanCanChange) {
  const world::GroundTruth truth = two_fruits();
  SemanticOcTree map(SemanticMapParams{}, SemanticClasses{});
  ScanInserter ins(map);
  IncrementalEvaluator inc(truth, MetricsParams{});
  inc.update(map, {});
  EXPECT_EQ(inc.last_rescored_points(), truth.fruits[0].surface_points.size() + truth.fruits[1].surface_points.size());
  // A view of the first fruit from +x: points of the second fruit's far side are not re-scored,
  // and the figures still equal the full evaluation.
  CameraIntrinsics K;
  const std::vector<synth::Sphere> scene = {{Vec3(0.4, 0.2, 1.0), 0.04, 2, 7}};
  const LabelledFrame f = synth::render_spheres(K, synth::look_at(Vec3(0.4, -0.2, 1.0), Vec3(0.4, 0.2, 1.0)), scene);
  ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
  const MapMetrics& got = inc.update(map, ins.last_updates());
  expect_same_metrics(got, evaluate_map(map, truth, MetricsParams{}));
  EXPECT_GT(got.paper.covered, 0u);
  EXPECT_GT(inc.last_rescored_points(), 0u);
  EXPECT_LT(inc.last_rescored_points(), truth.fruits[0].surface_points.size());
  // A second, empty batch re-scores nothing.
  inc.update(map, {});
  EXPECT_EQ(inc.last_rescored_points(), 0u);
  EXPECT_EQ(inc.last_rescored_fruits(), 0u);
}

TEST(FruitClusters, DoNotDependOnTheOrderOfTheVoxels) {
  std::vector<Vec3> v;
  const double res = 0.015;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) v.emplace_back((i + 0.5) * res + 0.1, (j + 0.5) * res, 1.0 + 0.3 * res * i);
  for (int i = 0; i < 3; ++i) v.emplace_back(0.5 + (i + 0.5) * res, 0.5 * res, 1.0);
  const std::vector<FruitCluster> a = fruit_clusters(v, res, 1);
  std::vector<Vec3> shuffled = v;
  std::mt19937 rng(3);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const std::vector<FruitCluster> b = fruit_clusters(shuffled, res, 1);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].voxels, b[i].voxels);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a[i].centroid[k], b[i].centroid[k]);
      EXPECT_EQ(a[i].semi_axes[k], b[i].semi_axes[k]);
    }
    EXPECT_EQ(a[i].ellipsoid_volume_m3, b[i].ellipsoid_volume_m3);
  }
}

// Matching finds its candidate pairs with a KD-tree of fruit centres: the same detection as
// testing every cluster against every fruit (a slow reference written here), on random scenes.
TEST(FruitDetection, KdTreeCandidatesEqualEveryPair) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> pos(0.0, 1.0), size(0.03, 0.12), jitter(-0.05, 0.05);
  for (int scene = 0; scene < 20; ++scene) {
    world::GroundTruth truth;
    for (int i = 0; i < 40; ++i) {
      world::FruitTruth f;
      f.instance_id = i;
      f.target = i % 7 != 0;
      f.center = Vec3(pos(rng), pos(rng), pos(rng));
      const double s = size(rng);
      f.bbox_min = f.center - Vec3(s / 2, s / 3, s / 4);
      f.bbox_max = f.center + Vec3(s / 2, s / 3, s / 4);
      f.volume_m3 = s * s * s / 3;
      truth.fruits.push_back(f);
    }
    std::vector<FruitCluster> clusters;
    for (int i = 0; i < 50; ++i) {
      FruitCluster c;
      c.centroid = i < 35 ? Vec3(truth.fruits[std::size_t(i)].center + Vec3(jitter(rng), jitter(rng), jitter(rng)))
                          : Vec3(pos(rng), pos(rng), pos(rng));
      c.voxels = 10;
      c.voxel_volume_m3 = 1e-4;
      c.ellipsoid_volume_m3 = 2e-4;
      clusters.push_back(c);
    }
    const FruitDetection got = detect_fruits(clusters, truth, 0.5);
    // Reference: every pair.
    std::vector<const world::FruitTruth*> targets;
    for (const world::FruitTruth& f : truth.fruits)
      if (f.target) targets.push_back(&f);
    std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
    for (std::size_t c = 0; c < clusters.size(); ++c)
      for (std::size_t f = 0; f < targets.size(); ++f) {
        const double dist = (clusters[c].centroid - targets[f]->center).norm();
        if (dist <= 0.5 * (targets[f]->bbox_max - targets[f]->bbox_min).maxCoeff()) pairs.emplace_back(dist, c, f);
      }
    std::sort(pairs.begin(), pairs.end());
    std::vector<bool> cu(clusters.size()), fu(targets.size());
    std::vector<std::pair<int, int>> want;
    for (const auto& [dist, c, f] : pairs) {
      if (cu[c] || fu[f]) continue;
      cu[c] = fu[f] = true;
      want.emplace_back(int(c), targets[f]->instance_id);
    }
    ASSERT_EQ(got.matches.size(), want.size()) << "scene " << scene;
    EXPECT_GT(want.size(), 4u);  // the scenes have matches to agree on
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(got.matches[i].cluster, want[i].first);
      EXPECT_EQ(got.matches[i].instance_id, want[i].second);
    }
  }
}
