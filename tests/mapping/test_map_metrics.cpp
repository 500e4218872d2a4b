#include <gtest/gtest.h>

#include "canopy/mapping/map_metrics.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/perception/semantic_extractor.h"
#include "synthetic.h"

using namespace canopy;
using namespace canopy::mapping;

namespace {
const Vec3 kCenter(0.4, 0.2, 1.0);
constexpr double kRadius = 0.04;

SemanticOcTree make_map() { return SemanticOcTree(SemanticMapParams{}, SemanticClasses{}); }

world::GroundTruth sphere_truth() {
  world::GroundTruth t;
  t.fruits.push_back(synth::sphere_truth(kCenter, kRadius, 0.003, 7));
  return t;
}

void insert_view(ScanInserter& ins, const Vec3& eye, const Vec3& up = Vec3::UnitZ()) {
  CameraIntrinsics K;
  const std::vector<synth::Sphere> scene = {{kCenter, kRadius, 2, 7}};
  const LabelledFrame f = synth::render_spheres(K, synth::look_at(eye, kCenter, up), scene);
  ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
}
}  // namespace

TEST(MapMetrics, NoViewsGiveZeroCoverageAndUnseenEntropy) {
  SemanticOcTree map = make_map();
  const MapMetrics m = evaluate_map(map, sphere_truth(), MetricsParams{});
  EXPECT_EQ(m.coverage, 0.0);
  EXPECT_EQ(m.covered, 0u);
  EXPECT_GT(m.points, 2000u);
  ASSERT_EQ(m.fruits.size(), 1u);
  EXPECT_EQ(m.fruits[0].box_unknown, m.fruits[0].box_voxels);
  EXPECT_NEAR(m.total_entropy, map.unseen_entropy() * double(m.fruits[0].box_voxels), 1e-6);
  // 0.1 m box at 0.015 m: 6 or 7 voxel centres per axis.
  EXPECT_GE(m.fruits[0].box_voxels, 216u);
  EXPECT_LE(m.fruits[0].box_voxels, 343u);
}

TEST(MapMetrics, FruitSeenFromSixSidesIsCovered) {
  SemanticOcTree map = make_map();
  ScanInserter ins(map);
  const double d = 0.4;
  insert_view(ins, kCenter + Vec3(d, 0, 0));
  insert_view(ins, kCenter - Vec3(d, 0, 0));
  insert_view(ins, kCenter + Vec3(0, d, 0));
  insert_view(ins, kCenter - Vec3(0, d, 0));
  insert_view(ins, kCenter + Vec3(0, 0, d), Vec3::UnitY());
  insert_view(ins, kCenter - Vec3(0, 0, d), Vec3::UnitY());
  const MapMetrics m = evaluate_map(map, sphere_truth(), MetricsParams{});
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_EQ(m.fruits[0].coverage, m.coverage);
  EXPECT_GT(m.target_voxels, 50u);
  // One view covers about half the sphere at most.
  SemanticOcTree one = make_map();
  ScanInserter ins1(one);
  insert_view(ins1, kCenter + Vec3(d, 0, 0));
  const MapMetrics m1 = evaluate_map(one, sphere_truth(), MetricsParams{});
  EXPECT_GT(m1.coverage, 0.3);
  EXPECT_LT(m1.coverage, 0.7);
  EXPECT_LT(m.total_entropy, m1.total_entropy);
}

TEST(MapMetrics, RepeatedConsistentViewsLowerEntropyMonotonically) {
  SemanticOcTree map = make_map();
  ScanInserter ins(map);
  const Vec3 half = Vec3::Constant(0.05);
  double last = box_entropy(map, kCenter - half, kCenter + half);
  for (int i = 0; i < 12; ++i) {
    insert_view(ins, kCenter + Vec3(0.4, 0.0, 0.0));
    const double h = box_entropy(map, kCenter - half, kCenter + half);
    EXPECT_LT(h, last) << "view " << i + 1;
    last = h;
  }
}

TEST(MapMetrics, CoverageUsesOnlyTargetVoxels) {
  // The same sphere labelled leaf gives no fruit coverage.
  SemanticOcTree map = make_map();
  ScanInserter ins(map);
  CameraIntrinsics K;
  const std::vector<synth::Sphere> scene = {{kCenter, kRadius, 1}};
  const LabelledFrame f = synth::render_spheres(K, synth::look_at(kCenter + Vec3(0.4, 0, 0), kCenter), scene);
  ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
  const MapMetrics m = evaluate_map(map, sphere_truth(), MetricsParams{});
  EXPECT_EQ(m.covered, 0u);
  EXPECT_EQ(m.target_voxels, 0u);
  EXPECT_GT(m.counts.occupied, 50u);
  const nlohmann::json j = m.to_json();
  EXPECT_EQ(j["fruits"].size(), 1u);
  EXPECT_EQ(j["fruits"][0]["instance_id"], 7);
}
