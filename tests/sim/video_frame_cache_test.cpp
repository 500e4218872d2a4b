// The video frame cache's own arithmetic, without a renderer: the robot's screen rectangle
// holds every pixel its geoms' bounding spheres project to, the caption box holds every pixel
// the caption changed, and a composed frame takes each pixel from the nearer of robot and
// world. (That cached frames look as full renders is tested on the renderer, in
// render_culling_test.cpp.)

#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <cmath>
#include <vector>

#include "canopy/common/random.h"
#include "canopy/sim/video_frame_cache.h"

namespace canopy::sim {
namespace {

mjvGeom sphere_geom(const Vec3& c, double r, int objid) {
  mjvGeom g{};
  for (int i = 0; i < 3; ++i) g.pos[i] = static_cast<float>(c[i]);
  for (int i = 0; i < 9; ++i) g.mat[i] = i % 4 == 0 ? 1.f : 0.f;
  g.modelrbound = static_cast<float>(r);
  g.objid = objid;
  return g;
}

mjvScene scene_of(std::vector<mjvGeom>& geoms) {
  mjvScene s{};
  s.geoms = geoms.data();
  s.ngeom = static_cast<int>(geoms.size());
  return s;
}

bool inside(const ScreenRect& r, int x, int y) {
  return x >= r[0] && x < r[0] + r[2] && y >= r[1] && y < r[1] + r[3];
}

// Property: for random cameras and spheres in front of them, every point of every sphere that
// lands in the frame lands in the rectangle (OpenGL row = H / 2 - f y / z).
TEST(VideoFrameCache, TheScreenRectHoldsEveryProjectedPointOfTheGeoms) {
  Rng rng(5);
  const int W = 160, H = 120;
  const double f = 100.0, near_m = 0.05;
  for (int trial = 0; trial < 50; ++trial) {
    const Pose T_world_camera =
        make_pose(Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)),
                  Quat(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized());
    std::vector<mjvGeom> geoms;
    std::vector<std::pair<Vec3, double>> spheres;  // camera frame
    for (int k = 0; k < 3; ++k) {
      const Vec3 c_cam(rng.uniform(-0.8, 0.8), rng.uniform(-0.6, 0.6), rng.uniform(1.0, 3.0));
      const double r = rng.uniform(0.02, 0.2);
      spheres.push_back({c_cam, r});
      geoms.push_back(sphere_geom(T_world_camera * c_cam, r, k));
    }
    const mjvScene scene = scene_of(geoms);
    const ScreenRect rect = geoms_screen_rect(scene, T_world_camera, f, W, H, near_m);
    for (const auto& [c, r] : spheres)
      for (int s = 0; s < 400; ++s) {
        const Vec3 d(rng.normal(), rng.normal(), rng.normal());
        const Vec3 p = c + r * d.normalized();
        const double u = f * p.x() / p.z() + 0.5 * W, row = 0.5 * H - f * p.y() / p.z();
        const int x = static_cast<int>(std::floor(u)), y = static_cast<int>(std::floor(row));
        if (x < 0 || x >= W || y < 0 || y >= H) continue;
        EXPECT_TRUE(inside(rect, x, y)) << "trial " << trial << " pixel " << x << "," << y;
      }
  }
  // A geom without a bound, or one reaching the near plane, gives the whole frame.
  std::vector<mjvGeom> unbounded{sphere_geom(Vec3(0, 0, 2), 0.0, 0)};
  EXPECT_EQ(geoms_screen_rect(scene_of(unbounded), Pose::Identity(), f, W, H, near_m), (ScreenRect{0, 0, W, H}));
  std::vector<mjvGeom> behind{sphere_geom(Vec3(0, 0, -2), 0.1, 0)};
  EXPECT_EQ(geoms_screen_rect(scene_of(behind), Pose::Identity(), f, W, H, near_m), (ScreenRect{0, 0, W, H}));
}

TEST(VideoFrameCache, RectanglesOverlapOnlyWhenTheyShareAPixel) {
  EXPECT_TRUE(rects_overlap({0, 0, 4, 4}, {3, 3, 2, 2}));
  EXPECT_FALSE(rects_overlap({0, 0, 4, 4}, {4, 0, 2, 2}));  // edge to edge
  EXPECT_FALSE(rects_overlap({0, 0, 0, 4}, {0, 0, 4, 4}));  // empty
}

// Property: the composed frame is, pixel by pixel, the robot where its depth is below the
// world's inside the robot's rectangle, and the captioned world everywhere else; a repeated
// robot is the last frame again; the caption box holds every changed pixel.
TEST(VideoFrameCache, AComposedFrameTakesTheNearerOfRobotAndWorld) {
  const int W = 64, H = 48;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  Rng rng(11);
  std::vector<unsigned char> world(3 * n);
  std::vector<float> world_depth(n);
  for (auto& v : world) v = static_cast<unsigned char>(rng.integer(0, 255));
  for (auto& d : world_depth) d = static_cast<float>(rng.uniform(0.2, 1.0));
  VideoFrameCache cache(W, H);
  EXPECT_FALSE(cache.camera_still(make_pose(Vec3(1, 0, 0), Quat::Identity()), false));
  EXPECT_TRUE(cache.camera_still(make_pose(Vec3(1, 0, 0), Quat::Identity()), false));
  EXPECT_FALSE(cache.camera_still(make_pose(Vec3(1, 0, 0), Quat::Identity()), true));  // shadows
  cache.keep_world(world, world_depth);
  ASSERT_TRUE(cache.needs_caption("cap"));
  std::vector<unsigned char> captioned = world;
  for (int y = 40; y < 44; ++y)
    for (int x = 2; x < 20; ++x) captioned[3 * (static_cast<std::size_t>(y) * W + x)] ^= 0xff;
  cache.set_captioned_world(captioned, "cap");
  EXPECT_EQ(cache.caption_box(), (ScreenRect{0, 36, 24, 12}));  // 2..19 x 40..43, padded by 4, clipped
  cache.end_frame("cap");
  EXPECT_FALSE(cache.needs_caption("cap"));
  EXPECT_TRUE(cache.needs_caption("other"));

  std::vector<mjvGeom> robot{sphere_geom(Vec3(0.1, -0.05, 1.5), 0.15, 3)};
  const mjvScene scene = scene_of(robot);
  ASSERT_TRUE(cache.robot_changed(scene, /*redraw=*/true));
  EXPECT_EQ(cache.last_path(), VideoPath::kRobotOnly);
  const ScreenRect rect = cache.start_robot(scene, Pose::Identity(), 40.0, 0.05);
  ASSERT_GT(cache.robot_rect_pixels(), 0);
  EXPECT_LT(cache.robot_rect_pixels(), static_cast<long>(n));
  const std::size_t m = static_cast<std::size_t>(rect[2]) * rect[3];
  std::vector<unsigned char> robot_rgb(3 * m);
  std::vector<float> robot_depth(m);
  for (auto& v : robot_rgb) v = static_cast<unsigned char>(rng.integer(0, 255));
  for (auto& d : robot_depth) d = static_cast<float>(rng.uniform(0.0, 1.2));
  cache.compose_robot(robot_rgb, robot_depth);
  const std::vector<unsigned char>& frame = cache.frame_rgb();
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t f = static_cast<std::size_t>(y) * W + x;
      const unsigned char* want = &captioned[3 * f];
      if (inside(rect, x, y)) {
        const std::size_t s = static_cast<std::size_t>(y - rect[1]) * rect[2] + (x - rect[0]);
        if (robot_depth[s] < world_depth[f]) want = &robot_rgb[3 * s];
      }
      for (int c = 0; c < 3; ++c) ASSERT_EQ(frame[3 * f + c], want[c]) << x << "," << y;
    }
  // The same robot again: the last frame, nothing to draw.
  EXPECT_FALSE(cache.robot_changed(scene, /*redraw=*/false));
  EXPECT_EQ(cache.last_path(), VideoPath::kReused);
  // The robot moved out of view: its old rectangle goes back to the captioned world.
  std::vector<mjvGeom> away{sphere_geom(Vec3(50, 0, 1.5), 0.15, 3)};
  const mjvScene away_scene = scene_of(away);
  ASSERT_TRUE(cache.robot_changed(away_scene, false));
  cache.start_robot(away_scene, Pose::Identity(), 40.0, 0.05);
  EXPECT_EQ(cache.robot_rect_pixels(), 0);
  EXPECT_EQ(cache.frame_rgb(), captioned);
  cache.full_frame();
  EXPECT_FALSE(cache.has_world());
  EXPECT_EQ(cache.last_path(), VideoPath::kFull);
}

}  // namespace
}  // namespace canopy::sim
