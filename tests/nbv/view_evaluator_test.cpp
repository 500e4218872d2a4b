// The view evaluator (nbv/view_evaluator.h): the fast ray casting against the slow reference,
// and the defined answers of bad views.

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/nbv/view_evaluator.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;
using nbv_test::Fixture;

// Fast and reference evaluations give the same gain for every gain and ray set.
TEST(ViewEvaluator, FastEqualsReferenceForEveryGainAndRaySet) {
  Fixture f;
  ViewEvaluator eval(f.index, f.K, f.params.rays);
  const auto cands = sample_candidates(nbv_test::kFruitA, 0, f.params.candidates);
  int positive = 0;
  for (const auto& gname : gain_names()) {
    const auto gain = make_gain(gname, f.params.gain);
    for (const auto& rname : ray_set_names()) {
      for (std::size_t i = 0; i < cands.size(); i += 7) {
        const ViewScore a = eval.evaluate(cands[i].T_world_camera, cands[i].target, *gain, ray_set(rname), i);
        const ViewScore b = eval.evaluate_reference(cands[i].T_world_camera, cands[i].target, *gain, ray_set(rname), i);
        EXPECT_EQ(a.status, b.status);
        EXPECT_EQ(a.rays, b.rays);
        EXPECT_EQ(a.voxels, b.voxels);
        EXPECT_NEAR(a.gain, b.gain, 1e-9 * std::max(1.0, std::fabs(b.gain))) << gname << " " << rname << " " << i;
        positive += a.gain > 0.0;
      }
    }
  }
  EXPECT_GT(positive, 100);
}

TEST(ViewEvaluator, BadViewsScoreZeroWithAStatus) {
  Fixture f;
  ViewEvaluator eval(f.index, f.K, f.params.rays);
  const auto gain = make_gain("osamcep", f.params.gain);
  // camera inside the fruit (an occupied voxel)
  octomap::OcTreeKey k;
  Vec3 inside;
  bool found = false;
  f.map.for_each_leaf([&](const octomap::OcTreeKey& key, unsigned depth, const mapping::SemanticState& s) {
    if (!found && depth == 16 && s.occupancy() > 0.9) {
      inside = f.map.center_of(key);
      found = true;
    }
  });
  ASSERT_TRUE(found);
  ViewScore s = eval.evaluate(look_at(inside, inside + Vec3(0.3, 0, 0)), inside + Vec3(0.3, 0, 0), *gain,
                              ray_set("ours"), 0);
  EXPECT_EQ(s.status, ViewStatus::kInsideOccupied);
  EXPECT_EQ(s.gain, 0.0);
  // target behind the camera
  const Pose T = look_at(Vec3(0, 0, 1), Vec3(1, 0, 1));
  s = eval.evaluate(T, Vec3(-1, 0, 1), *gain, ray_set("ours"), 0);
  EXPECT_EQ(s.status, ViewStatus::kTargetBehind);
  EXPECT_EQ(s.gain, 0.0);
  // target far off-axis: the window misses the image
  s = eval.evaluate(T, Vec3(1, 5, 1), *gain, ray_set("ours"), 0);
  EXPECT_EQ(s.status, ViewStatus::kNoRays);
  EXPECT_EQ(s.gain, 0.0);
  // camera outside the map
  s = eval.evaluate(look_at(Vec3(1e4, 0, 0), Vec3(0, 0, 0)), Vec3(0, 0, 0), *gain, ray_set("ours"), 0);
  EXPECT_EQ(s.status, ViewStatus::kOutsideMap);
  EXPECT_STREQ(to_string(s.status), "camera outside the map");
  // a centroid at the edge of the map: rays run into unknown space, the gain stays finite
  const Vec3 edge(0.5, 0.15, 1.6);
  const auto cands = sample_candidates(edge, 0, f.params.candidates);
  for (const auto& g : gain_names())
    for (const auto& c : cands) {
      const ViewScore e = eval.evaluate(c.T_world_camera, c.target, *make_gain(g, f.params.gain), ray_set("dense"), 0);
      EXPECT_TRUE(std::isfinite(e.gain));
      EXPECT_GE(e.gain, 0.0);
    }
  (void)k;
}

