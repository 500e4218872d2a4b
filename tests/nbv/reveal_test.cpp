// canopy's own planner reveal (nbv/planners/reveal/) on the small analytic scene: views scored
// by the fruit surface they reveal, best first, at most max_views, tried one at a time
// (kUtility), tagged "reveal"; a view tried before the one taken failed and is not offered
// again at the stop; a taken one never again. In the mission: tests/mission/mission_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>

#include "canopy/nbv/planners/reveal/reveal.h"
#include "canopy/nbv/voxel_index.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

bool same_pose(const Pose& a, const Pose& b) { return a.isApprox(b, 1e-12); }

}  // namespace

TEST(Reveal, ViewsRevealSurfaceBestFirstOneAtATime) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map(2);
  VoxelIndex index(map);
  ViewPlannerSettings s;
  s.method.name = "reveal";
  s.params.planner<RevealParams>().max_views = 3;
  // The scene was scanned from two views only: let sight lines cross its unknown space (occupied
  // voxels still block them).
  s.params.planner<RevealParams>().unknown_pass = 1000;
  const auto planner = make_view_planner(s);
  EXPECT_EQ(planner->name(), "reveal");
  ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.region = Eigen::AlignedBox3d(Vec3(0.2, -0.3, 0.7), Vec3(0.8, 0.6, 1.4));
  const ViewBatch first = planner->next(req);
  ASSERT_FALSE(first.views.empty()) << first.reason;
  EXPECT_LE(first.views.size(), 3u);
  EXPECT_EQ(first.order, BatchOrder::kUtility);
  EXPECT_GE(first.clusters, 2u);
  for (std::size_t i = 0; i < first.views.size(); ++i) {
    EXPECT_GE(first.views[i].gain, 1.0);  // at least one surface voxel
    EXPECT_EQ(first.views[i].source, "reveal");
    if (i) {
      EXPECT_LE(first.views[i].gain, first.views[i - 1].gain);
    }
  }
  // The first view failed, the second was taken: neither comes back at this stop.
  planner->taken(first.views.size() > 1 ? first.views[1].T_world_camera : first.views[0].T_world_camera);
  const ViewBatch second = planner->next(req);
  const std::size_t gone = std::min<std::size_t>(2, first.views.size());
  for (const PlannedView& v : second.views)
    for (std::size_t i = 0; i < gone; ++i) EXPECT_FALSE(same_pose(v.T_world_camera, first.views[i].T_world_camera));
  // A reach test that refuses everything leaves no view, with the reason.
  req.reach = [](Candidate*) { return false; };
  const ViewBatch none = planner->next(req);
  EXPECT_TRUE(none.finished);
  EXPECT_EQ(none.reason, "every candidate was filtered out");
}
