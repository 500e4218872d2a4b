// The frontier planner's pieces on hand-built maps (planners/frontier/frontier.h): its targets, the
// inflated ROI field, the single-ray utility and the camera orientation, each against values
// worked out by hand.

#include <gtest/gtest.h>

#include "canopy/common/camera.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/nbv/planners/frontier/frontier.h"
#include "canopy/nbv/voxel_index.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

constexpr int kLeaf = 1, kFruit = 2;  // the default classes: background, leaf, fruit

mapping::SemanticOcTree empty_map() {
  mapping::SemanticMapParams p;
  p.threads = 1;
  p.prune = false;
  return mapping::SemanticOcTree(p, SemanticClasses{});
}

octomap::OcTreeKey key(int dx, int dy, int dz) {
  const int k0 = mapping::kKeyOrigin;
  return octomap::OcTreeKey(static_cast<octomap::key_type>(k0 + dx), static_cast<octomap::key_type>(k0 + dy),
                            static_cast<octomap::key_type>(k0 + dz));
}

// A voxel observed free `passes` times (five passes take p_occ below 0.4).
void make_free(mapping::SemanticOcTree& map, const octomap::OcTreeKey& k, int passes = 5) {
  for (int i = 0; i < passes; ++i) map.update_free(k);
}

}  // namespace

// R: a fruit voxel (ROI). F: a free voxel beside it, with unknown neighbours: an ROI contour
// target and an exploration target whose normal points away from R. L: a leaf voxel with the
// free voxel M beside it: an exploration target only. G: an isolated free voxel (no occupied
// neighbour): no target. H: a free voxel whose six neighbours are all known: no target.
TEST(Frontier, TargetsOnAHandBuiltMap) {
  mapping::SemanticOcTree map = empty_map();
  map.update_hit(key(0, 0, 0), kFruit);                       // R
  make_free(map, key(1, 0, 0));                               // F
  map.update_hit(key(0, 3, 0), kLeaf);                        // L
  make_free(map, key(0, 4, 0));                               // M
  make_free(map, key(6, 0, 0));                               // G
  const int hx = -6;                                          // H and its known neighbours
  make_free(map, key(hx, 0, 0));
  for (const auto& d : {std::array<int, 3>{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}})
    make_free(map, key(hx + d[0], d[1], d[2]));
  VoxelIndex index(map);
  const Eigen::AlignedBox3d region(Vec3::Constant(-0.2), Vec3::Constant(0.2));
  const frontier::Targets t = frontier::find_targets(index, region);

  ASSERT_EQ(t.roi.size(), 1u);
  EXPECT_TRUE(t.roi[0].isApprox(map.center_of(key(0, 0, 0))));
  ASSERT_EQ(t.roi_contour.size(), 1u);
  EXPECT_TRUE(t.roi_contour[0].isApprox(map.center_of(key(1, 0, 0))));
  // Loop order z, y, x: F (y = 0) before M (y = 4). H's neighbours each have unknown
  // neighbours but no occupied one, so they are no exploration targets either.
  ASSERT_EQ(t.exploration.size(), 2u);
  EXPECT_TRUE(t.exploration[0].isApprox(map.center_of(key(1, 0, 0))));
  EXPECT_TRUE(t.exploration[1].isApprox(map.center_of(key(0, 4, 0))));
  ASSERT_EQ(t.exploration_normals.size(), 2u);
  EXPECT_TRUE(t.exploration_normals[0].isApprox(Vec3::UnitX()));
  EXPECT_TRUE(t.exploration_normals[1].isApprox(Vec3::UnitY()));
  // Outside the region nothing is found.
  const frontier::Targets none =
      frontier::find_targets(index, Eigen::AlignedBox3d(Vec3::Constant(1.0), Vec3::Constant(1.2)));
  EXPECT_TRUE(none.roi.empty() && none.roi_contour.empty() && none.exploration.empty());
}

// The field is 1 - distance / radius from the nearest ROI point, sampled at cell centres.
TEST(Frontier, InflatedRoiFallsLinearlyToZeroAtTheRadius) {
  // Region from the origin; with radius 0.3 and cells of 0.05 the grid starts at -0.3, so
  // cell centres lie at -0.275 + 0.05 i and p0 is one of them.
  const Vec3 p0(0.025, 0.025, 0.025);
  const frontier::InflatedRoi roi({p0}, Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Constant(0.5)), 0.3, 0.05);
  EXPECT_NEAR(roi.at(p0), 1.0, 1e-6);
  EXPECT_NEAR(roi.at(p0 + Vec3(0.15, 0, 0)), 0.5, 1e-6);
  EXPECT_NEAR(roi.at(p0 + Vec3(0.05, 0.05, 0)), 1.0 - std::sqrt(2.0) * 0.05 / 0.3, 1e-6);
  EXPECT_NEAR(roi.at(p0 + Vec3(0, 0, 0.25)), 1.0 - 0.25 / 0.3, 1e-6);
  EXPECT_EQ(roi.at(p0 + Vec3(0.35, 0, 0)), 0.0);   // beyond the radius
  EXPECT_EQ(roi.at(Vec3(5.0, 5.0, 5.0)), 0.0);     // outside the grid
  // The nearest ROI point decides.
  const frontier::InflatedRoi two({p0, p0 + Vec3(0.2, 0, 0)}, Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Constant(0.5)),
                                  0.3, 0.05);
  EXPECT_NEAR(two.at(p0 + Vec3(0.15, 0, 0)), 1.0 - 0.05 / 0.3, 1e-6);
}

// A ray of ten voxels along x: unknown voxels add 0.5 each (no ROI near), free ones nothing,
// the first voxel with p > 0.6 ends it, and the sum is divided by the ten voxels.
TEST(Frontier, RayUtilityCountsUnknownVoxelsUntilTheFirstOccupiedOne) {
  mapping::SemanticOcTree map = empty_map();
  const FrontierParams params;
  const Vec3 origin = map.center_of(key(0, 0, 0));
  const Vec3 target = map.center_of(key(10, 0, 0));
  const frontier::InflatedRoi no_roi({}, Eigen::AlignedBox3d(Vec3::Constant(-1), Vec3::Constant(1)), 0.3, 0.05);
  {
    VoxelIndex index(map);
    EXPECT_NEAR(frontier::ray_utility(index, no_roi, params, origin, target), 0.5, 1e-12);
  }
  make_free(map, key(3, 0, 0));
  {
    VoxelIndex index(map);
    EXPECT_NEAR(frontier::ray_utility(index, no_roi, params, origin, target), 9 * 0.5 / 10, 1e-12);
  }
  // Freed once, p_occ = 0.475: inside (0.4, 0.6], so still unknown to this utility.
  map.update_free(key(4, 0, 0));
  {
    VoxelIndex index(map);
    EXPECT_NEAR(frontier::ray_utility(index, no_roi, params, origin, target), 9 * 0.5 / 10, 1e-12);
  }
  map.update_hit(key(6, 0, 0), kLeaf);  // p_occ about 0.79
  {
    VoxelIndex index(map);
    // Voxels 0..5 count, voxel 3 adds nothing: 5 x 0.5 over the ray's 10 voxels.
    EXPECT_NEAR(frontier::ray_utility(index, no_roi, params, origin, target), 5 * 0.5 / 10, 1e-12);
    // An ROI around the ray raises every unknown voxel's share.
    const frontier::InflatedRoi roi({map.center_of(key(2, 0, 0))}, Eigen::AlignedBox3d(Vec3::Constant(-1), Vec3::Constant(1)),
                                    0.3, 0.05);
    EXPECT_GT(frontier::ray_utility(index, roi, params, origin, target), 5 * 0.5 / 10);
    EXPECT_LE(frontier::ray_utility(index, roi, params, origin, target), 5 * 1.0 / 10);
  }
}

// point_at turns the camera by the smallest rotation that puts its optical axis on the target.
TEST(Frontier, PointAtIsTheSmallestRotationOntoTheTarget) {
  const Vec3 eye(0.1, -0.2, 0.9);
  const Pose current = look_at(eye, Vec3(0.5, 0.3, 1.0));
  for (const Vec3& target : {Vec3(0.5, 0.3, 1.0), Vec3(0.7, 0.0, 0.6), Vec3(-0.3, 0.4, 1.4)}) {
    const Pose T = frontier::point_at(current, eye, target);
    EXPECT_TRUE(T.translation().isApprox(eye));
    EXPECT_LT((T.linear().col(2) - (target - eye).normalized()).norm(), 1e-12);
    EXPECT_LT((T.linear().transpose() * T.linear() - Mat3::Identity()).norm(), 1e-12);
    EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
    // The rotation between the two orientations is exactly the angle between the optical axes.
    const double turn = Eigen::AngleAxisd(current.linear().transpose() * T.linear()).angle();
    const Vec3 a = current.linear().col(2), b = T.linear().col(2);
    const double axes = std::atan2(a.cross(b).norm(), a.dot(b));
    EXPECT_NEAR(turn, axes, 1e-9);
  }
  // Already looking at it: unchanged.
  EXPECT_LT((frontier::point_at(current, eye, Vec3(0.5, 0.3, 1.0)).linear() - current.linear()).norm(), 1e-9);
}

// The goal test at planning (nbv.frontier.goal_test_at_planning, the default): the batch holds
// only views that pass ViewRequest::goal_free, in utility order, at most five, the dropped ones
// counted as filtered; with the test off (the authors' code) views that fail it are sent too.
TEST(Frontier, TheGoalTestAtPlanningKeepsOnlyViewsThatWouldNotFailBeforeTheMove) {
  mapping::SemanticOcTree map = empty_map();
  map.update_hit(key(0, 0, 0), kFruit);  // R with its contour F: ROI views around F
  make_free(map, key(1, 0, 0));
  VoxelIndex index(map);
  ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.region = Eigen::AlignedBox3d(Vec3::Constant(-0.2), Vec3::Constant(0.2));
  req.T_world_camera = look_at(Vec3(0.4, 0.0, 0.0), Vec3::Zero());
  req.seed = 7;
  // "No free goal" for every camera below the target's height.
  const auto free_goal = [](const PlannedView& v) { return v.T_world_camera.translation().z() >= v.target.z(); };
  auto planner = [](bool test) {
    ViewPlannerSettings s;
    s.method.name = "frontier";
    s.params.planner<FrontierParams>().roi_utility_threshold = -1e9;  // always the ROI views
    s.params.planner<FrontierParams>().goal_test_at_planning = test;
    return make_view_planner(s);
  };
  const ViewBatch off = planner(false)->next(req);
  req.goal_free = free_goal;
  const ViewBatch sent = planner(false)->next(req);
  const ViewBatch kept = planner(true)->next(req);
  EXPECT_EQ(sent.views.size(), off.views.size());  // off: goal_free is never asked
  ASSERT_GT(off.views.size(), 5u);
  std::size_t failing = 0;
  for (const PlannedView& v : off.views) failing += !free_goal(v);
  ASSERT_GT(failing, 0u) << "no sampled view fails the test: the test tests nothing";
  // Kept: the first five passing views of the same utility order, nothing else.
  std::vector<PlannedView> expected;
  std::size_t dropped = 0;
  for (const PlannedView& v : off.views) {
    if (expected.size() == 5) break;
    if (free_goal(v)) expected.push_back(v);
    else ++dropped;
  }
  ASSERT_EQ(kept.views.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_TRUE(kept.views[i].T_world_camera.isApprox(expected[i].T_world_camera)) << i;
    EXPECT_TRUE(free_goal(kept.views[i]));
  }
  EXPECT_EQ(kept.filtered, off.filtered + dropped);
}
