// The pixels a view casts rays through (nbv/ray_sets.h): ours' grid against its formulas (count,
// step, centre, clipping at the image border) and the dense and sparse grids over the image.

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/nbv/ray_sets.h"

using namespace canopy;
using namespace canopy::nbv;

// Ours at z = 0.4 m: b = 95.3 px, ds = 14.3 px, a proper 7 x 7 grid centred on the target.
TEST(RaySets, OursIsAProperGrid) {
  CameraIntrinsics K;
  RayParams p;
  std::vector<Vec2> px;
  ray_set("ours").pixels(K, p, RayWindow{200.0, 200.0, 0.4}, &px);
  ASSERT_EQ(px.size(), 49u);
  const double ds = 0.015 * 381.36 / 0.4;
  Vec2 mean = Vec2::Zero();
  for (const auto& q : px) mean += q / 49.0;
  EXPECT_NEAR(mean.x(), 200.0, 1e-9);
  EXPECT_NEAR(mean.y(), 200.0, 1e-9);
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) {
      EXPECT_NEAR(px[j * 7 + i].x(), 200.0 + (i - 3) * ds, 1e-9);
      EXPECT_NEAR(px[j * 7 + i].y(), 200.0 + (j - 3) * ds, 1e-9);  // rows are not sheared
    }
  // Near the border part of the grid falls outside; far outside none is left.
  ray_set("ours").pixels(K, p, RayWindow{2.0, 200.0, 0.4}, &px);
  EXPECT_EQ(px.size(), 28u);
  ray_set("ours").pixels(K, p, RayWindow{-500.0, 200.0, 0.4}, &px);
  EXPECT_TRUE(px.empty());
  ray_set("ours").pixels(K, p, RayWindow{200.0, 200.0, 0.0}, &px);
  EXPECT_TRUE(px.empty());
}

TEST(RaySets, DenseAndSparseCoverTheImage) {
  CameraIntrinsics K;
  std::vector<Vec2> px;
  ray_set("dense").pixels(K, RayParams{}, RayWindow{}, &px);
  EXPECT_EQ(px.size(), 784u);
  ray_set("sparse").pixels(K, RayParams{}, RayWindow{}, &px);
  ASSERT_EQ(px.size(), 36u);
  EXPECT_NEAR(px.front().x(), 400.0 / 12, 1e-9);
  EXPECT_NEAR(px.back().y(), 400.0 - 400.0 / 12, 1e-9);
  EXPECT_EQ(ray_set_names(), (std::vector<std::string>{"ours", "dense", "sparse"}));
  EXPECT_THROW(ray_set("all", "--rays"), InputError);
}

// The window scales with depth: at any depth the grid has floor(L / delta S) + 1 points a side
// (the window and the step both scale as fx / z), the step is delta S fx / z, and an unknown
// name is refused naming where it came from and the valid names.
TEST(RaySets, OursGridKeepsItsCountAndScalesItsStepWithDepth) {
  CameraIntrinsics K;
  K.width_px = K.height_px = 4000;  // room for the near windows
  K.cx_px = K.cy_px = 2000.0;
  RayParams p;
  p.cluster_size_m = 0.1;
  p.step_m = 0.02;  // 6 points a side
  std::vector<Vec2> px;
  for (double z : {0.1, 0.25, 0.5, 1.0, 2.0}) {
    ray_set("ours").pixels(K, p, RayWindow{2000.0, 1500.0, z}, &px);
    ASSERT_EQ(px.size(), 36u) << z;
    const double ds = p.step_m * K.fx_px / z;
    EXPECT_NEAR(px[1].x() - px[0].x(), ds, 1e-9) << z;
    EXPECT_NEAR(px[6].y() - px[0].y(), ds, 1e-9) << z;
    EXPECT_NEAR(px.back().x() - px.front().x(), 5 * ds, 1e-9) << z;  // the window b = L fx / z
    EXPECT_NEAR(0.5 * (px.front().y() + px.back().y()), 1500.0, 1e-9) << z;
  }
  for (const double bad : {-1.0, std::nan("")}) {
    ray_set("ours").pixels(K, p, RayWindow{2000.0, 1500.0, bad}, &px);
    EXPECT_TRUE(px.empty()) << bad;
  }
  try {
    ray_set("all", "--rays");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--rays: unknown ray set 'all' (valid: ours, dense, sparse)");
  }
}
