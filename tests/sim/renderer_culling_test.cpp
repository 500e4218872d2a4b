// Frustum culling draws only what the camera can see: frames rendered with culling are
// identical, pixel for pixel (RGB, depth, classes, instances), to frames of the full scene,
// on the default world's plants with the robot, for wrist-camera poses and a shadowed chase
// view; and a camera looking at one plant draws a small part of the scene.

#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/sim/renderer.h"

namespace canopy::sim {
namespace {

// A chase-like camera: w x h pixels, 60 degree vertical field of view, 0.01-50 m.
CameraIntrinsics chase_intrinsics(int w, int h) {
  CameraIntrinsics K;
  K.width_px = w;
  K.height_px = h;
  K.cx_px = w / 2.0;
  K.cy_px = h / 2.0;
  K.fx_px = K.fy_px = (h / 2.0) / std::tan(M_PI / 6);
  K.min_range_m = 0.01;
  K.max_range_m = 50.0;
  return K;
}


struct DefaultWorld {
  world::World world;
  Simulator sim;
  static world::WorldSpec spec() {
    world::WorldSpec s = world::WorldSpec::load(find_data_file("worlds/default.yaml"));
    s.rows.plants_per_row = 8;  // 16 plants: most of the row lies outside any one view
    return s;
  }
  DefaultWorld() : world(world::generate_world(spec())), sim(world, default_robot_config()) {}
};

DefaultWorld& scene() {
  static DefaultWorld w;
  return w;
}

// Counts pixels that differ; identical frames give 0 everywhere.
struct Diff {
  long rgb = 0, depth = 0, cls = 0, inst = 0;
};
Diff compare(const LabelledFrame& a, const LabelledFrame& b) {
  Diff d;
  for (std::size_t i = 0; i < a.rgb.data.size(); ++i) {
    const Rgb8 &p = a.rgb.data[i], &q = b.rgb.data[i];
    d.rgb += p.r != q.r || p.g != q.g || p.b != q.b;
    d.depth += a.depth_m.data[i] != b.depth_m.data[i];
    d.cls += a.class_id.data[i] != b.class_id.data[i];
    d.inst += a.instance.data[i] != b.instance.data[i];
  }
  return d;
}

// Behind and above the base looking ahead along the aisle (as the mission video's chase view).
Pose chase(const BasePose& b) {
  const Vec3 heading(std::cos(b.yaw_rad), std::sin(b.yaw_rad), 0.0), ground(b.x_m, b.y_m, 0.0);
  return look_at(ground - 1.6 * heading + Vec3(0, 0, 1.9), ground + 0.9 * heading + Vec3(0, 0, 0.6));
}

TEST(RenderCulling, MeshVerticesLieInsideTheModelBoundingSphere) {
  const mjModel* m = scene().sim.render_model();
  int meshes = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_type[g] != mjGEOM_MESH) continue;
    const int id = m->geom_dataid[g];
    ASSERT_GE(id, 0);
    ++meshes;
    for (int v = m->mesh_vertadr[id]; v < m->mesh_vertadr[id] + m->mesh_vertnum[id]; ++v) {
      const float* p = m->mesh_vert + 3 * v;
      ASSERT_LE(std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]), m->geom_rbound[g] + 1e-6)
          << "geom " << g;
    }
  }
  EXPECT_GT(meshes, 100);
}

TEST(RenderCulling, WristFramesAreIdenticalWithAndWithoutCulling) {
  DefaultWorld& w = scene();
  const CameraIntrinsics& K = w.world.spec.camera;
  Renderer culled(w.sim, K, RenderOptions{false, 1, true}), full(w.sim, K, RenderOptions{false, 1, true});
  full.set_culling(false);
  const RobotConfig cfg = default_robot_config();
  Rng rng(5);
  int fewer = 0;
  for (int k = 0; k < 8; ++k) {
    // Along the aisle, arm at home or in random configurations (plants, ground, sky, robot).
    const BasePose base{-0.6 + 0.55 * k, rng.uniform(-0.05, 0.05), rng.uniform(-0.2, 0.2)};
    ArmConfig q = cfg.home;
    if (k % 4 != 0)
      for (auto& v : q) v = rng.uniform(-M_PI, M_PI);
    w.sim.set_robot_state(base, q);
    const LabelledFrame a = culled.render_wrist_camera();
    const LabelledFrame b = full.render_wrist_camera();
    const Diff d = compare(a, b);
    EXPECT_EQ(d.rgb, 0) << "pose " << k;
    EXPECT_EQ(d.depth, 0) << "pose " << k;
    EXPECT_EQ(d.cls, 0) << "pose " << k;
    EXPECT_EQ(d.inst, 0) << "pose " << k;
    EXPECT_EQ(full.last_drawn_geom_count(), full.last_scene_geom_count());
    EXPECT_LE(culled.last_drawn_geom_count(), culled.last_scene_geom_count());
    fewer += culled.last_drawn_geom_count() < culled.last_scene_geom_count();
  }
  EXPECT_GE(fewer, 6);  // culling is not a no-op
}

TEST(RenderCulling, ShadowedChaseViewsAreIdenticalWithAndWithoutCulling) {
  DefaultWorld& w = scene();
  const CameraIntrinsics K = chase_intrinsics(640, 480);
  Renderer culled(w.sim, K, RenderOptions{true, 1, false}), full(w.sim, K, RenderOptions{true, 1, false});
  full.set_culling(false);
  const RobotConfig cfg = default_robot_config();
  int fewer = 0;
  for (int k = 0; k < 6; ++k) {
    const BasePose base{-0.8 + 0.9 * k, 0.0, k == 5 ? M_PI : 0.0};  // the last one looks back
    w.sim.set_robot_state(base, cfg.home);
    const Pose T = chase(base);
    const LabelledFrame a = culled.render(T, true, true);
    const LabelledFrame b = full.render(T, true, true);
    const Diff d = compare(a, b);
    EXPECT_EQ(d.rgb, 0) << "pose " << k;
    EXPECT_EQ(d.depth, 0) << "pose " << k;
    EXPECT_EQ(d.cls, 0) << "pose " << k;
    EXPECT_EQ(d.inst, 0) << "pose " << k;
    fewer += culled.last_drawn_geom_count() < culled.last_scene_geom_count();
    // The captioned RGB frame of the video, too.
    const Image<Rgb8> ca = culled.render_captioned(T, true, "stop 1/5");
    const Image<Rgb8> cb = full.render_captioned(T, true, "stop 1/5");
    EXPECT_TRUE(ca.data == cb.data) << "pose " << k;
  }
  EXPECT_GE(fewer, 3);
}

// The depth-only truth render (unlit, only the depth read back) draws the very depth of a full
// render without the robot: bit for bit, at the camera's size and a quarter of it (the
// oracle's truth renders), with depth noise too (the same draws), the robot anywhere.
TEST(RenderCulling, DepthOnlyRenderIsTheFullRendersDepthBitForBit) {
  DefaultWorld& w = scene();
  const CameraIntrinsics& K = w.world.spec.camera;
  CameraIntrinsics quarter = K;
  quarter.width_px = K.width_px / 4;
  quarter.height_px = K.height_px / 4;
  quarter.fx_px = K.fx_px / 4;
  quarter.fy_px = K.fy_px / 4;
  quarter.cx_px = K.cx_px / 4;
  quarter.cy_px = K.cy_px / 4;
  quarter.depth_noise_k = 0.0;
  CameraIntrinsics noisy = K;
  noisy.depth_noise_k = 0.01;
  const RobotConfig cfg = default_robot_config();
  for (const CameraIntrinsics& C : {K, quarter, noisy}) {
    Renderer depth_only(w.sim, C, RenderOptions{false, 7, false}), full(w.sim, C, RenderOptions{false, 7, false});
    Rng rng(11);
    long seen = 0;
    for (int k = 0; k < 10; ++k) {
      const BasePose base{-0.6 + 0.45 * k, rng.uniform(-0.05, 0.05), rng.uniform(-0.2, 0.2)};
      ArmConfig q = cfg.home;
      if (k % 3 != 0)
        for (auto& v : q) v = rng.uniform(-M_PI, M_PI);
      w.sim.set_robot_state(base, q);
      // The wrist camera's pose, and one looking at a plant from the aisle.
      const world::Plant& plant = w.world.plants[std::size_t(k) % w.world.plants.size()];
      const Vec3 target = plant.base_position + Vec3(0, 0, rng.uniform(0.3, 0.9));
      const Pose poses[2] = {w.sim.camera_pose(),
                             look_at(target + Vec3(rng.uniform(-0.3, 0.3), rng.uniform(0.25, 0.6) * (k % 2 ? 1 : -1),
                                                   rng.uniform(-0.2, 0.3)),
                                     target)};
      for (const Pose& T : poses) {
        const Image<float> a = depth_only.render_depth(T);
        const Image<float> b = full.render(T, false, false).depth_m;
        ASSERT_EQ(a.data.size(), b.data.size());
        long differ = 0;
        for (std::size_t i = 0; i < a.data.size(); ++i) {
          differ += std::memcmp(&a.data[i], &b.data[i], sizeof(float)) != 0;
          seen += a.data[i] > 0.f;
        }
        EXPECT_EQ(differ, 0) << C.width_px << " px, pose " << k;
      }
    }
    EXPECT_GT(seen, 20 * long(C.width_px) * C.height_px / 100) << C.width_px << " px: too little in range to compare";
  }
}

// Cameras looking down at the ground where leaves outside the view cast their shadows (the
// sun shines along (-0.3, 0.2, -1); its shadow map covers 2 m around the origin).
TEST(RenderCulling, ShadowsOfGeomsOutsideTheViewAreKept) {
  DefaultWorld& w = scene();
  CameraIntrinsics K;
  K.width_px = 320;
  K.height_px = 240;
  K.cx_px = 160;
  K.cy_px = 120;
  K.fx_px = K.fy_px = 400.0;
  K.min_range_m = 0.01;
  K.max_range_m = 50.0;
  Renderer culled(w.sim, K, RenderOptions{true, 1, false}), full(w.sim, K, RenderOptions{true, 1, false}),
      unshadowed(w.sim, K, RenderOptions{false, 1, false});
  full.set_culling(false);
  w.sim.set_robot_state(BasePose{-3.0, 0.0, 0.0}, default_robot_config().home);  // the robot out of the way
  const Vec3 shadow_dir = Vec3(-0.3, 0.2, 0.0);                                      // per metre of height
  int shadowed_and_culled = 0;
  for (const world::Plant& plant : w.world.plants) {
    if (plant.base_position.norm() > 1.6) continue;
    for (double h : {0.6, 0.9, 1.2}) {
      const Vec3 ground = plant.base_position + h * shadow_dir;
      const Vec3 eye = ground + Vec3(0, 0, 0.25);
      const Pose T = look_at(eye, ground);
      const LabelledFrame a = culled.render(T, false, true);
      const LabelledFrame b = full.render(T, false, true);
      const Diff d = compare(a, b);
      EXPECT_EQ(d.rgb, 0) << "plant " << plant.index << " height " << h;
      EXPECT_EQ(d.depth, 0) << "plant " << plant.index << " height " << h;
      EXPECT_EQ(d.cls, 0) << "plant " << plant.index << " height " << h;
      const LabelledFrame c = unshadowed.render(T, false, true);
      shadowed_and_culled += compare(a, c).rgb > 1000 && culled.last_drawn_geom_count() < culled.last_scene_geom_count();
    }
  }
  EXPECT_GE(shadowed_and_culled, 3);  // shadows in view, geoms culled
}

// How far a video frame is from the full render: pixels that differ at all, and the largest
// difference of one channel.
struct ImageDiff {
  long pixels = 0;
  int max_level = 0;
};
ImageDiff image_diff(const Image<Rgb8>& a, const Image<Rgb8>& b) {
  ImageDiff d;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const Rgb8 &p = a.data[i], &q = b.data[i];
    const int level = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
    d.pixels += level > 0;
    d.max_level = std::max(d.max_level, level);
  }
  return d;
}

// Video frames of a still camera (the world kept, the robot drawn in its screen rectangle and
// composited by depth) look as full renders. They are not always bit-identical: the robot's
// rectangle is drawn with an off-centre frustum, whose projection matrix rounds differently in
// float, so llvmpipe's colour interpolation can land one level apart on a few pixels (seen: 1
// pixel, 1 level, in 3 of 12 frames). Allowed: 0.05 % of the pixels, 3 levels.
void expect_looks_as_full_render(const Image<Rgb8>& video, const Image<Rgb8>& full, const std::string& what) {
  const ImageDiff d = image_diff(video, full);
  EXPECT_LE(d.pixels * 2000, static_cast<long>(video.data.size())) << what;
  EXPECT_LE(d.max_level, 3) << what;
}

TEST(RenderVideoFrame, LooksAsTheFullRenderWhileTheArmMovesUnderAStillCamera) {
  DefaultWorld& w = scene();
  const CameraIntrinsics K = chase_intrinsics(320, 240);
  Renderer video(w.sim, K), full(w.sim, K);
  const RobotConfig cfg = default_robot_config();
  Rng rng(9);
  int robot_only = 0;
  for (int k = 0; k < 12; ++k) {
    const BasePose base{k < 8 ? 0.4 : 1.3, 0.0, 0.0};  // still for 8 frames, then moved
    ArmConfig q = cfg.home;
    for (auto& v : q) v += rng.uniform(-0.6, 0.6);
    w.sim.set_robot_state(base, q);
    const std::string caption = k < 5 ? "stop 1/5 | views 3" : "stop 1/5 | views 4";
    const Pose T = chase(base);
    const Image<Rgb8> a = video.render_video_frame(T, caption);
    expect_looks_as_full_render(a, full.render_captioned(T, true, caption), "frame " + std::to_string(k));
    if (video.last_video_path() == Renderer::VideoPath::kRobotOnly) {
      ++robot_only;
      EXPECT_GT(video.last_robot_rect_pixels(), 0);
      EXPECT_LT(video.last_robot_rect_pixels(), K.width_px * K.height_px);  // a part of the frame
    }
  }
  EXPECT_GE(robot_only, 9);  // every frame but the first and the one after the move
}

// The arm swung into the plant rows on both sides, in front of some leaves and behind others:
// the depth composite hides it where the full render does.
TEST(RenderVideoFrame, TheArmAmongThePlantsIsHiddenWhereTheFullRenderHidesIt) {
  DefaultWorld& w = scene();
  const CameraIntrinsics K = chase_intrinsics(320, 240);
  Renderer video(w.sim, K), full(w.sim, K);
  const RobotConfig cfg = default_robot_config();
  const world::Plant& plant = w.world.plants.front();
  const BasePose base{plant.base_position.x(), 0.0, 0.0};  // beside the first plants
  const Pose T = chase(base);
  Rng rng(21);
  long robot_pixels = 0;
  for (int k = 0; k < 10; ++k) {
    ArmConfig q = cfg.home;
    for (auto& v : q) v += rng.uniform(-1.5, 1.5);
    w.sim.set_robot_state(base, q);
    const Image<Rgb8> a = video.render_video_frame(T, "");
    const Image<Rgb8> with_robot = full.render_captioned(T, true, "");
    expect_looks_as_full_render(a, with_robot, "pose " + std::to_string(k));
    robot_pixels += image_diff(with_robot, full.render_captioned(T, false, "")).pixels;
  }
  EXPECT_GT(robot_pixels, 1000);  // the arm is in view
}

// A frame whose robot, camera and caption repeat is the last frame again, drawn not at all; a
// new caption is drawn over the kept world.
TEST(RenderVideoFrame, ARepeatedStateGivesTheLastFrameWithoutDrawing) {
  DefaultWorld& w = scene();
  const CameraIntrinsics K = chase_intrinsics(320, 240);
  Renderer video(w.sim, K), full(w.sim, K);
  const BasePose base{0.8, 0.0, 0.0};
  w.sim.set_robot_state(base, default_robot_config().home);
  const Pose T = chase(base);
  video.render_video_frame(T, "a");  // the camera arrives: a full frame
  const Image<Rgb8> first = video.render_video_frame(T, "a");
  EXPECT_EQ(video.last_video_path(), Renderer::VideoPath::kRobotOnly);
  const Image<Rgb8> again = video.render_video_frame(T, "a");
  EXPECT_EQ(video.last_video_path(), Renderer::VideoPath::kReused);
  EXPECT_EQ(image_diff(first, again).pixels, 0);
  const Image<Rgb8> captioned = video.render_video_frame(T, "stop 2/5 | views 7 | SC 0.41");
  EXPECT_EQ(video.last_video_path(), Renderer::VideoPath::kRobotOnly);
  expect_looks_as_full_render(captioned, full.render_captioned(T, true, "stop 2/5 | views 7 | SC 0.41"), "new caption");
  EXPECT_GT(image_diff(captioned, again).pixels, 50);  // the caption changed
}

// The video's coarser cylinders (RenderOptions::primitive_slices / _stacks): the world
// without the robot renders the same but for the sky (MuJoCo draws the skybox as a sphere,
// about 10 m away here), the robot with far fewer triangles and nearly the same pixels, and
// video frames still look as full renders with the same options. Tessellations MuJoCo cannot
// draw are refused.
TEST(RenderVideoFrame, CoarseCylindersDrawFewerTrianglesAndChangeOnlyTheRobot) {
  DefaultWorld& w = scene();
  const CameraIntrinsics K = chase_intrinsics(320, 240);
  RenderOptions coarse;
  coarse.primitive_slices = 12;
  coarse.primitive_stacks = 2;
  Renderer fine_r(w.sim, K), coarse_r(w.sim, K, coarse), coarse_video(w.sim, K, coarse);
  const BasePose base{0.6, 0.0, 0.0};
  ArmConfig q = default_robot_config().home;
  w.sim.set_robot_state(base, q);
  const Pose T = chase(base);
  const LabelledFrame world_fine = fine_r.render(T, /*show_robot=*/false, /*labels=*/false);
  const long world_triangles = fine_r.last_triangle_count();
  const LabelledFrame world_coarse = coarse_r.render(T, false, false);
  EXPECT_EQ(coarse_r.last_triangle_count(), world_triangles);
  long sky = 0, elsewhere = 0;
  for (std::size_t i = 0; i < world_fine.depth_m.data.size(); ++i) {
    const float a = world_fine.depth_m.data[i], b = world_coarse.depth_m.data[i];
    if (a == b && world_fine.rgb.data[i] == world_coarse.rgb.data[i]) continue;
    (std::min(a, b) > 9.0f ? sky : elsewhere) += 1;
  }
  EXPECT_EQ(elsewhere, 0);
  EXPECT_GT(sky, 0);

  const LabelledFrame robot_fine = fine_r.render(T, true, true);
  const long fine_robot_triangles = fine_r.last_triangle_count() - world_triangles;
  const LabelledFrame robot_coarse = coarse_r.render(T, true, true);
  const long coarse_robot_triangles = coarse_r.last_triangle_count() - world_triangles;
  EXPECT_GT(coarse_robot_triangles, 0);
  EXPECT_LT(coarse_robot_triangles * 4, fine_robot_triangles);
  long robot_pixels = 0;
  for (std::size_t i = 0; i < robot_fine.class_id.data.size(); ++i)
    robot_pixels += robot_fine.depth_m.data[i] != world_fine.depth_m.data[i];
  const ImageDiff d = image_diff(robot_fine.rgb, robot_coarse.rgb);
  EXPECT_GT(robot_pixels, 1000);          // the robot is in view
  EXPECT_GT(d.pixels, 0);                 // and drawn differently
  EXPECT_LT(d.pixels * 4, robot_pixels);  // on its facets' edges and shading only

  Rng rng(4);
  for (int k = 0; k < 4; ++k) {
    for (auto& v : q) v += rng.uniform(-0.3, 0.3);
    w.sim.set_robot_state(base, q);
    expect_looks_as_full_render(coarse_video.render_video_frame(T, "views 3"),
                                coarse_r.render_captioned(T, true, "views 3"), "frame " + std::to_string(k));
  }

  for (const auto& [slices, stacks] : {std::pair{2, 4}, std::pair{-1, 0}, std::pair{12, -3}, std::pair{12, 1}}) {
    RenderOptions bad;
    bad.primitive_slices = slices;
    bad.primitive_stacks = stacks;
    EXPECT_THROW(Renderer(w.sim, K, bad), InputError) << slices << " " << stacks;
  }
}

TEST(RenderCulling, ACameraLookingAtOnePlantDrawsFewGeoms) {
  DefaultWorld& w = scene();
  const world::Plant& plant = w.world.plants.front();
  const CameraIntrinsics& K = w.world.spec.camera;
  Renderer renderer(w.sim, K);
  // 0.45 m in front of the first plant, at mid height, looking at it across the aisle.
  const Vec3 base = plant.base_position;
  const double side = base.y() > 0 ? -1.0 : 1.0;
  const Vec3 eye = base + Vec3(0, side * 0.45, 0.6);
  const LabelledFrame f = renderer.render_free_camera(look_at(eye, eye - Vec3(0, side, 0)));
  long leafy = 0;
  for (auto c : f.class_id.data) leafy += c != 0;
  EXPECT_GT(leafy, 1000);  // the plant is in view
  const int scene_geoms = renderer.last_scene_geom_count(), drawn = renderer.last_drawn_geom_count();
  std::size_t parts = 0;
  for (const world::Plant& p : w.world.plants) parts += p.parts.size();
  EXPECT_GE(static_cast<std::size_t>(scene_geoms), parts);  // the scene holds every plant part
  EXPECT_LT(drawn * 4, scene_geoms) << drawn << " of " << scene_geoms;
  EXPECT_GT(drawn, 1);
}

}  // namespace
}  // namespace canopy::sim
