// The shape-completion planner (nbv/planners/shape/) and the fitted fruits it plans on
// (nbv/fruit_shapes.h), on a hand-built scene: one fruit mapped from the front only, so its back
// half is predicted, not seen; a leaf hides that back half from the +y side. The view that sees
// the hidden half wins; the view behind the leaf scores under half its mirror (and under half
// what it scores without the leaf); the front, seen already, scores least.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../mapping/synthetic.h"
#include "scene.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/nbv/fruit_shapes.h"
#include "canopy/nbv/planners/shape/shape.h"
#include "canopy/nbv/voxel_index.h"
#include "canopy/perception/semantic_extractor.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

using nbv_test::front_map;
using nbv_test::kShapeFruit;
using nbv_test::kShapeLeaf;
using nbv_test::kShapeRadius;

struct Scored {
  Pose T;
  double gain;
};

// Every candidate the planner scored, and its batch.
std::vector<Scored> plan(const mapping::SemanticOcTree& map, ViewBatch* batch,
                         const std::string& other_class = "refute") {
  VoxelIndex index(map);
  ViewPlannerSettings s;
  s.method.name = "shape";
  s.params.planner<ShapeParams>().other_class = other_class;
  const auto planner = make_view_planner(s);
  EXPECT_EQ(planner->name(), "shape");
  ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.region = Eigen::AlignedBox3d(Vec3(0.2, -0.4, 0.6), Vec3(0.8, 0.4, 1.4));
  std::vector<Scored> all;
  req.on_scored = [&](const ScoredView& v) { all.push_back({v.candidate.T_world_camera, v.score.gain}); };
  *batch = planner->next(req);
  return all;
}

// The gain of the scored candidate whose camera lies closest to kShapeFruit + 0.4 (cos a, sin a, 0).
double gain_at(const std::vector<Scored>& all, double azimuth_deg) {
  const Vec3 want = kShapeFruit + 0.4 * Vec3(std::cos(azimuth_deg * M_PI / 180), std::sin(azimuth_deg * M_PI / 180), 0.0);
  const auto it = std::min_element(all.begin(), all.end(), [&](const Scored& a, const Scored& b) {
    return (a.T.translation() - want).norm() < (b.T.translation() - want).norm();
  });
  EXPECT_LT((it->T.translation() - want).norm(), 0.03);
  return it->gain;
}

}  // namespace

// The fit completes the fruit from its front: centre within 1 cm (the voxels' centroid is
// over 1.5 cm in front of it), and about half the predicted surface is still to be seen.
TEST(FruitShapes, FrontScanPredictsTheBackHalf) {
  const mapping::SemanticOcTree map = front_map(false);
  std::vector<Vec3> confirmed;
  const auto fruits = fit_fruits(map, ClusterParams{}, mapping::ShapeFitParams{}, nullptr, 0.1, &confirmed);
  ASSERT_EQ(fruits.size(), 1u);
  ASSERT_TRUE(fruits[0].shape.ok);
  EXPECT_LT((fruits[0].shape.centre - kShapeFruit).norm(), 0.01) << fruits[0].shape.centre.transpose();
  EXPECT_GT((fruits[0].cluster.centroid - kShapeFruit).norm(), 0.015);
  const auto unseen = unseen_surface(fruits, confirmed, 0.01, 0.015);
  const auto all = mapping::shape_surface_spaced(fruits[0].shape, 0.01);
  EXPECT_GT(unseen.size(), all.size() / 4);
  EXPECT_LT(unseen.size(), all.size() * 3 / 4);
  // The unseen points lie on the back (+x) side.
  for (const PredictedPoint& p : unseen) EXPECT_GT(p.position.x(), fruits[0].shape.centre.x() - 0.02);
}

TEST(Shape, TheViewOfTheHiddenHalfWins) {
  ViewBatch batch;
  const std::vector<Scored> all = plan(front_map(true), &batch);
  ASSERT_FALSE(batch.views.empty()) << batch.reason;
  EXPECT_EQ(batch.order, BatchOrder::kUtility);
  EXPECT_EQ(batch.views.front().source, "shape");
  // The winner looks at the back (+x), not from the leaf's side (+y).
  const Vec3 best = batch.views.front().T_world_camera.translation() - kShapeFruit;
  EXPECT_GT(best.x(), 0.2) << best.transpose();
  EXPECT_LT(best.y(), 0.02) << best.transpose();
  // Back views at azimuth +-36 deg: the one behind the leaf scores less than its mirror.
  const double open = gain_at(all, -36.0), hidden = gain_at(all, 36.0), front = gain_at(all, 180.0);
  EXPECT_GT(open, 0.0);
  EXPECT_LT(hidden, 0.5 * open);
  EXPECT_LT(front, 0.25 * open);
  // The leaf is what costs the +y view: without it, that view scores over twice as much.
  ViewBatch bare;
  const std::vector<Scored> all_bare = plan(front_map(false), &bare);
  EXPECT_GT(gain_at(all_bare, 36.0), 2.0 * hidden);
}

// The fruit mapped from all around (24 views on a 0.4 m sphere).
mapping::SemanticOcTree all_around_map() {
  mapping::SemanticMapParams p;
  p.threads = 1;
  mapping::SemanticOcTree map(p, SemanticClasses{});
  mapping::ScanInserter ins(map);
  CameraIntrinsics K;
  const std::vector<synth::Sphere> spheres = {{kShapeFruit, kShapeRadius, 2, 0}};
  for (int v = 0; v < 8; ++v)
    for (const double z : {-0.25, 0.0, 0.25}) {
      const double a = 2 * M_PI * v / 8;
      const Vec3 eye = kShapeFruit + 0.4 * Vec3(std::cos(a), std::sin(a), z).normalized();
      const LabelledFrame f = synth::render_spheres(K, synth::look_at(eye, kShapeFruit), spheres);
      for (int i = 0; i < 2; ++i) ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
    }
  return map;
}

// Nothing left: a fruit mapped from all around has no unseen predicted surface.
TEST(Shape, DoneWhenTheWholeFruitIsSeen) {
  const mapping::SemanticOcTree map = all_around_map();
  std::vector<Vec3> confirmed;
  const auto fruits = fit_fruits(map, ClusterParams{}, mapping::ShapeFitParams{}, nullptr, 0.1, &confirmed);
  ASSERT_EQ(fruits.size(), 1u);
  EXPECT_LT((fruits[0].shape.centre - kShapeFruit).norm(), 0.005);
  const auto unseen = unseen_surface(fruits, confirmed, 0.01, 0.015);
  EXPECT_LT(unseen.size(), mapping::shape_surface_spaced(fruits[0].shape, 0.01).size() / 10);
}

// Segmentation noise: the fruit's back half seen once from behind but labelled leaf. The rule
// "refute" drops the predicted points there (another class's surface), so the view of the back
// is worth little; "fruit_probability" counts each by its voxel's fruit probability: more than
// refuted, less than while the back was unknown.
TEST(Shape, AMislabelledBackCountsByItsFruitProbability) {
  mapping::SemanticOcTree noisy = front_map(false);
  {
    mapping::ScanInserter ins(noisy);
    CameraIntrinsics K;
    const std::vector<synth::Sphere> as_leaf = {{kShapeFruit, kShapeRadius, 1, 0}};
    const LabelledFrame f = synth::render_spheres(K, synth::look_at(Vec3(0.9, 0.0, 1.0), kShapeFruit), as_leaf);
    ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
  }
  ViewBatch b1, b2, b3;
  const double unknown = gain_at(plan(front_map(false), &b1, "fruit_probability"), 0.0);
  const double refuted = gain_at(plan(noisy, &b2, "refute"), 0.0);
  const double weighted = gain_at(plan(noisy, &b3, "fruit_probability"), 0.0);
  EXPECT_EQ(unknown, gain_at(plan(front_map(false), &b1, "refute"), 0.0));  // no other class: the same
  EXPECT_GT(weighted, refuted + 1.0);
  EXPECT_LT(weighted, unknown);
}

// Nothing left to complete: with nbv.shape.fallback none the stop ends; with frontier that
// round is frontier's (its ROI / exploration views of the same map), and the reason says both.
TEST(Shape, FallsBackToFrontierWhenNoPredictedSurfaceIsLeft) {
  const mapping::SemanticOcTree map = all_around_map();
  VoxelIndex index(map);
  ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.region = Eigen::AlignedBox3d(Vec3(0.2, -0.4, 0.6), Vec3(0.8, 0.4, 1.4));
  ViewPlannerSettings s;
  s.method.name = "shape";
  const ViewBatch done = make_view_planner(s)->next(req);
  EXPECT_TRUE(done.finished);
  EXPECT_TRUE(done.views.empty());
  s.params.planner<ShapeParams>().fallback = "frontier";
  const ViewBatch fb = make_view_planner(s)->next(req);
  ASSERT_FALSE(fb.views.empty()) << fb.reason;
  for (const PlannedView& v : fb.views) EXPECT_TRUE(v.source == "roi" || v.source == "exploration") << v.source;
  EXPECT_EQ(fb.reason.rfind("shape: ", 0), 0u) << fb.reason;
  // The same views as frontier's own round on that request.
  s.method.name = "frontier";
  const ViewBatch own = make_view_planner(s)->next(req);
  ASSERT_EQ(own.views.size(), fb.views.size());
  for (std::size_t i = 0; i < own.views.size(); ++i)
    EXPECT_TRUE(own.views[i].T_world_camera.isApprox(fb.views[i].T_world_camera)) << i;
}
