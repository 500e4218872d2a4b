// ours (nbv/planners/ours/ours.h): the planner's views with their source tag, taken views never
// offered again. Its algorithm, the cluster planner, has its own test (cluster_planner_test.cpp).

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/nbv/planners/ours/ours.h"
#include "canopy/nbv/view_planner.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;
using nbv_test::Fixture;

// The planner through the registry: clusters not done, the taken-view rule before and after
// the reach test, views tagged "nbv" (the tag views.csv has always had for ours).
TEST(Ours, PlannerTakesNoViewTwiceAndTagsItsViews) {
  Fixture f;
  ViewPlannerSettings s;
  s.params = f.params;
  s.intrinsics = f.K;
  s.method.name = "ours";
  const auto planner = make_view_planner(s);
  EXPECT_EQ(planner->name(), "ours");
  ViewRequest req;
  req.map = &f.map;
  req.index = &f.index;
  req.region = Eigen::AlignedBox3d(Vec3(-1, -1, 0), Vec3(2, 2, 2));
  const ViewBatch first = planner->next(req);
  ASSERT_FALSE(first.views.empty());
  EXPECT_EQ(first.clusters, 2u);
  EXPECT_EQ(first.order, BatchOrder::kTour);
  for (const PlannedView& v : first.views) EXPECT_EQ(v.source, "nbv");
  for (const PlannedView& v : first.views) planner->taken(v.T_world_camera);
  const ViewBatch second = planner->next(req);
  for (const PlannedView& v : second.views) EXPECT_FALSE(planner->taken_views().contains(v.T_world_camera));
  // A reach test that refuses everything leaves nothing.
  req.reach = [](Candidate*) { return false; };
  const ViewBatch none = make_view_planner(s)->next(req);
  EXPECT_TRUE(none.views.empty());
  EXPECT_TRUE(none.finished);
  EXPECT_EQ(none.reason, "every candidate was filtered out");
}
