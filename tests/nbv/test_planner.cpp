#include <gtest/gtest.h>

#include <cmath>

#include "canopy/nbv/planner.h"
#include "canopy/nbv/view_planner.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

struct Fixture {
  mapping::SemanticOcTree map = nbv_test::scanned_map();
  VoxelIndex index{map};
  NbvParams params;
  CameraIntrinsics K;
};

}  // namespace

// Fast and reference evaluations give the same gain for every gain and ray set.
TEST(Planner, FastEqualsReferenceForEveryGainAndRaySet) {
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

TEST(Planner, TopKPerClusterBestFirst) {
  Fixture f;
  f.params.planner.top_k = 3;
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
TEST(Planner, NoClustersGivesAnEmptyPlan) {
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
TEST(Planner, FilterMovesTheScoredPose) {
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

TEST(Planner, FilteredOrDoneClustersGiveAReason) {
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

TEST(Planner, BadViewsScoreZeroWithAStatus) {
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

// A planner from outside the library joins the registry by name: settings may name it, the
// factory gets its settings (context included), and names are unique and well formed.
namespace {
struct ContextProbe : canopy::nbv::PlannerContext {
  int value = 42;
};
class FixedPlanner : public canopy::nbv::ViewPlanner {
 public:
  explicit FixedPlanner(const canopy::nbv::ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), seen_(dynamic_cast<const ContextProbe*>(s.context.get())) {}
  std::string name() const override { return "test-fixed"; }
  canopy::nbv::ViewBatch next(const canopy::nbv::ViewRequest&) override {
    canopy::nbv::ViewBatch b;
    b.finished = true;
    b.reason = seen_ ? "context " + std::to_string(seen_->value) : "no context";
    return b;
  }

 private:
  const ContextProbe* seen_;
};
}  // namespace

TEST(Planner, RegisteredPlannersAreMadeByName) {
  using namespace canopy::nbv;
  register_view_planner({"test-fixed", "a planner that plans nothing",
                         [](const ViewPlannerSettings& s) { return std::unique_ptr<ViewPlanner>(new FixedPlanner(s)); }});
  const std::vector<std::string> names = view_planner_names();
  ASSERT_GE(names.size(), 4u);
  EXPECT_EQ(names[0], "ours");
  EXPECT_EQ(names.back(), "test-fixed");
  ViewPlannerSettings s;
  s.method.name = "test-fixed";
  s.context = std::make_shared<ContextProbe>();
  const auto p = make_view_planner(s);
  EXPECT_EQ(p->name(), "test-fixed");
  EXPECT_EQ(p->next(ViewRequest{}).reason, "context 42");
  EXPECT_THROW(register_view_planner({"test-fixed", "again", [](const ViewPlannerSettings& x) {
                                        return std::unique_ptr<ViewPlanner>(new FixedPlanner(x));
                                      }}),
               canopy::InputError);
  EXPECT_THROW(register_view_planner({"Bad Name", "", [](const ViewPlannerSettings& x) {
                                        return std::unique_ptr<ViewPlanner>(new FixedPlanner(x));
                                      }}),
               canopy::InputError);
  s.method.name = "no-such";
  EXPECT_THROW(make_view_planner(s), canopy::InputError);
}
