#include <gtest/gtest.h>

#include <fstream>

#include "canopy/common/error.h"
#include "canopy/evaluation/view_presets.h"

using namespace canopy;
using namespace canopy::mapping;
using namespace canopy::evaluation;

TEST(Views, LookAtHasZeroRollAndLooksAtTheTarget) {  // canopy::look_at, used by the presets
  const Vec3 eye(1, 2, 0.5), target(1.3, 2.4, 0.7);
  const Pose T = look_at(eye, target);
  EXPECT_NEAR((T.linear().col(2) - (target - eye).normalized()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(T.linear().col(0).z(), 0.0, 1e-12);  // image x is horizontal
  EXPECT_LT(T.linear().col(1).z(), 0.0);           // image y (down) points down
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  const Pose down = look_at(Vec3(0, 0, 1), Vec3(0, 0, 0));
  EXPECT_NEAR(down.linear().determinant(), 1.0, 1e-12);
}

TEST(Views, RingCircleEachPlant) {
  world::World w;
  w.plants.resize(2);
  w.plants[0].base_position = Vec3(0, 0.75, 0);
  w.plants[0].height_m = 1.2;
  w.plants[1].base_position = Vec3(0.5, -0.75, 0);
  w.plants[1].height_m = 1.0;
  RingViews ring;
  const std::vector<Pose> v = ring_views(w, ring);
  ASSERT_EQ(v.size(), 2u * ring.heights.size() * ring.azimuths);
  // First view of each plant is on the aisle side, at the ring radius.
  EXPECT_LT(v[0].translation().y(), 0.75);
  EXPECT_NEAR((v[0].translation() - Vec3(0, 0.75, v[0].translation().z())).norm(), ring.radius_m, 1e-9);
  EXPECT_NEAR(v[0].translation().z(), 0.45 * 1.2, 1e-9);
}

TEST(Views, PoseFilesParseAndReportBadLines) {
  const std::string path = ::testing::TempDir() + "/views.txt";
  {
    std::ofstream f(path);
    f << "# x y z qw qx qy qz\n0.1 0.2 0.3 1 0 0 0\n\n0.4,0.5,0.6, 0,1,0,0  # comment\n";
  }
  const std::vector<Pose> v = load_views(path);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_NEAR((v[1].translation() - Vec3(0.4, 0.5, 0.6)).norm(), 0.0, 1e-12);
  {
    std::ofstream f(path);
    f << "0.1 0.2 0.3 2 0 0 0\n";
  }
  EXPECT_THROW(load_views(path), InputError);
  EXPECT_THROW(load_views("/nonexistent/views.txt"), InputError);
}
