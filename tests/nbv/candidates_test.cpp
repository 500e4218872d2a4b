#include <gtest/gtest.h>

#include "canopy/nbv/candidates.h"
#include "canopy/common/error.h"

using namespace canopy;
using namespace canopy::nbv;

TEST(Candidates, FiftyViewsOnTheSphereLookingAtTheCentroid) {
  const Vec3 c(1.0, 2.0, 1.0);
  const CandidateParams p;
  const auto cands = sample_candidates(c, 3, p);
  ASSERT_EQ(cands.size(), 50u);
  double min_polar = 1e9, max_polar = -1e9;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const Pose& T = cands[i].T_world_camera;
    EXPECT_NEAR((T.translation() - c).norm(), 0.4, 1e-12);
    EXPECT_EQ(cands[i].cluster, 3);
    // optical axis towards the centroid
    EXPECT_NEAR(T.linear().col(2).dot((c - T.translation()).normalized()), 1.0, 1e-12);
    // zero roll: x horizontal, image up (-y) has positive world z
    EXPECT_NEAR(T.linear().col(0).z(), 0.0, 1e-12);
    EXPECT_GT(-T.linear().col(1).z(), 0.0);
    EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
    min_polar = std::min(min_polar, cands[i].polar_deg);
    max_polar = std::max(max_polar, cands[i].polar_deg);
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_GT((cands[j].T_world_camera.translation() - T.translation()).norm(), 1e-3) << "duplicate " << i << " " << j;
  }
  EXPECT_DOUBLE_EQ(min_polar, 30.0);
  EXPECT_DOUBLE_EQ(max_polar, 150.0);
  EXPECT_DOUBLE_EQ(cands[9].azimuth_deg, 324.0);  // no 360
}

TEST(Candidates, BelowTheFloorDropped) {
  const auto cands = sample_candidates(Vec3(0, 0, 0.1), 0, CandidateParams{});
  EXPECT_LT(cands.size(), 50u);
  for (const auto& c : cands) EXPECT_GE(c.T_world_camera.translation().z(), 0.05);
}

TEST(Candidates, StraightDownHasAnUpVector) {
  const Pose T = look_at(Vec3(0, 0, 1), Vec3(0, 0, 0));
  EXPECT_TRUE(T.linear().allFinite());
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  EXPECT_NEAR(T.linear().col(2).z(), -1.0, 1e-12);
}
