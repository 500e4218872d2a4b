// The cluster planner (nbv/planners/ours/cluster_planner.h), ours' algorithm: the top-k views
// per cluster, its reasons for an empty plan, its filter, and ours' selection of candidates
// (which the oracle reuses) against the candidates the planner scores.

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/nbv/planners/ours/cluster_planner.h"
#include "canopy/nbv/view_planner.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;
using nbv_test::Fixture;

TEST(ClusterPlanner, TopKPerClusterBestFirst) {
  Fixture f;
  f.params.planner<OursParams>().top_k = 3;
  const auto clusters = find_clusters(f.map, f.params.cluster);
  ASSERT_EQ(clusters.size(), 2u);
  ClusterPlanner planner(f.params, f.K);
  const auto gain = make_gain("osamcep", f.params.gain);
  const Plan plan = planner.plan(f.index, clusters, *gain, ray_set("ours"), 1);
  EXPECT_TRUE(plan.reason.empty());
  EXPECT_EQ(plan.candidates, 100u);
  ASSERT_EQ(plan.clusters.size(), 2u);
  ASSERT_EQ(plan.views.size(), 6u);
  for (const auto& c : plan.clusters) {
    EXPECT_FALSE(c.done);
    ASSERT_EQ(c.top.size(), 3u);
    EXPECT_EQ(c.top[0].score.gain, c.best_gain);
    EXPECT_GE(c.top[0].score.gain, c.top[1].score.gain);
    EXPECT_GE(c.top[1].score.gain, c.top[2].score.gain);
  }
  for (std::size_t i = 1; i < plan.views.size(); ++i) EXPECT_GE(plan.views[i - 1].score.gain, plan.views[i].score.gain);
  // The scene was scanned from the -x side: the best view of fruit A looks from elsewhere.
  const Vec3 dir = (plan.clusters[0].top[0].candidate.T_world_camera.translation() - clusters[0].centroid).normalized();
  EXPECT_GT(dir.x(), -0.9);
  // Deterministic
  const Plan again = planner.plan(f.index, clusters, *gain, ray_set("ours"), 1);
  for (std::size_t i = 0; i < plan.views.size(); ++i) EXPECT_EQ(plan.views[i].score.gain, again.views[i].score.gain);
}

// Bad input: defined results with a reason, never NaN.
TEST(ClusterPlanner, NoClustersGivesAnEmptyPlan) {
  Fixture f;
  ClusterPlanner planner(f.params, f.K);
  const Plan plan = planner.plan(f.index, {}, *make_gain("osamcep", f.params.gain), ray_set("ours"), 1);
  EXPECT_TRUE(plan.views.empty());
  EXPECT_EQ(plan.reason, "no clusters");
  // an empty map has no clusters either
  mapping::SemanticOcTree empty(mapping::SemanticMapParams{}, SemanticClasses{});
  EXPECT_TRUE(find_clusters(empty, ClusterParams{}).empty());
  VoxelIndex ei(empty);
  ViewEvaluator eval(ei, f.K, f.params.rays);
  const auto c = sample_candidates(Vec3(0.5, 0, 1), 0, f.params.candidates);
  for (const auto& g : gain_names()) {
    const ViewScore s = eval.evaluate(c[0].T_world_camera, c[0].target, *make_gain(g, f.params.gain), ray_set("ours"), 0);
    EXPECT_TRUE(std::isfinite(s.gain)) << g;
    EXPECT_EQ(s.status, ViewStatus::kOk);
  }
}

// A filter that moves a candidate hands the moved pose (and its IK answer) to the scorer:
// the plan's views are the moved ones, scored where the camera will really be.
TEST(ClusterPlanner, FilterMovesTheScoredPose) {
  Fixture f;
  const auto clusters = find_clusters(f.map, f.params.cluster);
  ASSERT_FALSE(clusters.empty());
  ClusterPlanner planner(f.params, f.K);
  const auto gain = make_gain("osamcep", f.params.gain);
  const double shift = 0.05;
  const CandidateFilter move = [&](Candidate* c) {
    c->T_world_camera.translation() += shift * c->T_world_camera.linear().col(2);
    c->shift_m = shift;
    c->has_q = true;
    c->q = {1, 2, 3, 4, 5, 6};
    return true;
  };
  const Plan moved = planner.plan(f.index, clusters, *gain, ray_set("ours"), 1, move);
  ASSERT_FALSE(moved.views.empty());
  ViewEvaluator eval(f.index, f.K, f.params.rays);
  for (const ScoredView& v : moved.views) {
    EXPECT_TRUE(v.candidate.has_q);
    EXPECT_EQ(v.candidate.q[5], 6.0);
    EXPECT_NEAR((v.candidate.T_world_camera.translation() - v.candidate.target).norm(),
                f.params.candidates.sphere.radius_m - shift, 1e-9);
    const ViewScore s = eval.evaluate(v.candidate.T_world_camera, v.candidate.target, *gain, ray_set("ours"), 0);
    EXPECT_DOUBLE_EQ(s.gain, v.score.gain);
  }
}

TEST(ClusterPlanner, FilteredOrDoneClustersGiveAReason) {
  Fixture f;
  const auto clusters = find_clusters(f.map, f.params.cluster);
  ClusterPlanner planner(f.params, f.K);
  const auto gain = make_gain("osamcep", f.params.gain);
  const Plan none = planner.plan(f.index, clusters, *gain, ray_set("ours"), 1, [](Candidate*) { return false; });
  EXPECT_TRUE(none.views.empty());
  EXPECT_EQ(none.reason, "every candidate was filtered out");
  EXPECT_TRUE(none.clusters[0].done);
  // A cluster in a fully observed free region: nothing unknown or target near it -> done.
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  const Vec3 c(0.5, 0.0, 1.0);
  // Only voxels within max_dist of the target count for OSAMCEP: observe a box a bit larger.
  for (double x = -0.15; x <= 0.15; x += 0.015)
    for (double y = -0.15; y <= 0.15; y += 0.015)
      for (double z = -0.15; z <= 0.15; z += 0.015) {
        octomap::OcTreeKey k;
        ASSERT_TRUE(map.key_of(c + Vec3(x, y, z), &k));
        for (int i = 0; i < 40; ++i) map.update_free(k);
      }
  VoxelIndex index(map);
  Cluster cl;
  cl.centroid = c;
  cl.voxels = 3;
  const Plan done = planner.plan(index, {cl}, *gain, ray_set("ours"), 1);
  EXPECT_TRUE(done.views.empty());
  EXPECT_TRUE(done.clusters[0].done);
  EXPECT_EQ(done.reason, "every cluster is done (best gain <= 0)");
}


// ours_candidates is the selection ClusterPlanner::plan scores: same candidates, same order,
// same moves by the filter, same count of dropped ones.
TEST(ClusterPlanner, SelectionIsWhatThePlannerScores) {
  Fixture f;
  const auto clusters = find_clusters(f.map, f.params.cluster);
  ASSERT_EQ(clusters.size(), 2u);
  // Drop every third candidate, move the others 2 cm along the viewing direction.
  int calls = 0;
  const CandidateFilter filter = [&calls](Candidate* c) {
    if (++calls % 3 == 0) return false;
    c->T_world_camera.translation() += 0.02 * c->T_world_camera.linear().col(2);
    return true;
  };
  std::vector<ScoredView> scored;
  const Plan plan = ClusterPlanner(f.params, f.K)
                        .plan(f.index, clusters, *make_gain("osamcep", f.params.gain), ray_set("ours"), 1, filter,
                              [&](const ScoredView& v) { scored.push_back(v); });
  calls = 0;
  std::size_t filtered = 0;
  std::vector<KeptCandidate> kept;
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (const KeptCandidate& k : ours_candidates(clusters[c], int(c), f.params.candidates, filter, &filtered))
      kept.push_back(k);
  EXPECT_EQ(filtered, plan.filtered);
  EXPECT_GT(filtered, 0u);
  ASSERT_EQ(kept.size(), scored.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    EXPECT_TRUE(kept[i].candidate.T_world_camera.isApprox(scored[i].candidate.T_world_camera, 0.0)) << i;
    EXPECT_EQ(kept[i].candidate.cluster, scored[i].candidate.cluster);
  }
}
