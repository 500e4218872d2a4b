// Renderer against analytic ground truth: depth of a tilted plane and of a sphere, and the
// label of every geom in a test scene.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/sim/renderer.h"

namespace canopy::sim {
namespace {

// A scene with high tessellation quality so that spheres render within 0.1 mm.
std::string scene_xml(const std::string& body, int size_px = 400) {
  return "<mujoco><statistic extent=\"2\" center=\"0 0 0\"/><visual><global offwidth=\"" + std::to_string(size_px) +
         "\" offheight=\"" + std::to_string(size_px) +
         "\"/><quality offsamples=\"0\" numslices=\"200\" numstacks=\"200\"/><map znear=\"0.01\" zfar=\"10\"/></visual>"
         "<worldbody>" +
         body + "</worldbody></mujoco>";
}

// Camera at `eye` looking along `forward` with image-up towards +z.
Pose look(const Vec3& eye, const Vec3& forward) { return look_at(eye, eye + forward); }

TEST(Renderer, TiltedPlaneDepthMatchesAnalyticAtCentreAndCorners) {
  SceneDescription scene;
  scene.mjcf = scene_xml("<geom name=\"floor\" type=\"plane\" size=\"10 10 0.1\"/>");
  Simulator sim(scene);
  CameraIntrinsics K;
  K.max_range_m = 3.0;
  Renderer renderer(sim, K);
  // 0.6 m above the floor, pitched 25 degrees away from straight down.
  const double pitch = 25.0 * M_PI / 180.0;
  const Pose T = look(Vec3(0, 0, 0.6), Vec3(0, std::sin(pitch), -std::cos(pitch)));
  const LabelledFrame f = renderer.render_free_camera(T);
  const int pixels[][2] = {{199, 199}, {200, 200}, {0, 0}, {399, 0}, {0, 399}, {399, 399}, {57, 311}};
  for (const auto& px : pixels) {
    const Vec3 d_world = T.linear() * K.ray_direction(px[0] + 0.5, px[1] + 0.5);  // z-component 1 in camera
    const double t = -T.translation().z() / d_world.z();                         // hits z = 0
    const double z_expected = t;  // the camera-frame ray has unit z, so t is the z-depth
    EXPECT_NEAR(f.depth_m.at(px[0], px[1]), z_expected, 1e-3) << px[0] << "," << px[1];
  }
}

TEST(Renderer, SphereDepthMatchesRaySphereIntersection) {
  const Vec3 c(0.05, 0.5, 1.0);
  const double r = 0.12;
  SceneDescription scene;
  scene.mjcf = scene_xml("<geom name=\"ball\" type=\"sphere\" size=\"0.12\" pos=\"0.05 0.5 1.0\"/>");
  Simulator sim(scene);
  CameraIntrinsics K;
  Renderer renderer(sim, K);
  const Pose T = look(Vec3(0, 0, 1.02), Vec3(0, 1, 0));
  const LabelledFrame f = renderer.render_free_camera(T);
  int checked = 0;
  double worst = 0.0;
  for (int v = 0; v < K.height_px; v += 3)
    for (int u = 0; u < K.width_px; u += 3) {
      const Vec3 d = (T.linear() * K.ray_direction(u + 0.5, v + 0.5));  // camera z = 1
      const Vec3 o = T.translation();
      // |o + t d - c|^2 = r^2
      const double a = d.squaredNorm(), b = 2 * d.dot(o - c), cc = (o - c).squaredNorm() - r * r;
      const double disc = b * b - 4 * a * cc;
      if (disc <= 0) {
        if (disc < -0.02) {
          EXPECT_EQ(f.depth_m.at(u, v), 0.f) << "background pixel " << u << "," << v;
        }
        continue;
      }
      const double t = (-b - std::sqrt(disc)) / (2 * a);
      const Vec3 n = (o + t * d - c).normalized();
      if (-n.dot(d.normalized()) < 0.4) continue;  // skip grazing rays near the silhouette
      worst = std::max(worst, std::abs(f.depth_m.at(u, v) - t));
      ++checked;
    }
  EXPECT_GT(checked, 1000);
  EXPECT_LT(worst, 1e-3);
}

TEST(Renderer, LabelsAreRightForEveryGeomAndDepthRangeIsApplied) {
  // Boxes of different classes and instances in a row in front of the camera.
  SceneDescription scene;
  std::string body;
  const int n = 6;
  for (int i = 0; i < n; ++i) {
    const std::string name = "box" + std::to_string(i);
    body += "<geom name=\"" + name + "\" type=\"box\" size=\"0.03 0.03 0.03\" pos=\"" + std::to_string(-0.25 + 0.1 * i) +
            " 0.6 0\"/>";
    scene.labels[name] = GeomLabel{1 + i % 2, i % 2 == 1 ? 100 + i : kNoInstance, false};
  }
  // A far box beyond the max range: labelled but with invalid depth.
  body += "<geom name=\"far\" type=\"box\" size=\"0.2 0.01 0.2\" pos=\"0 1.8 0.3\"/>";
  scene.labels["far"] = GeomLabel{1, kNoInstance, false};
  scene.mjcf = scene_xml(body);
  Simulator sim(scene);
  CameraIntrinsics K;
  Renderer renderer(sim, K);
  const Pose T = look(Vec3(0, 0, 0), Vec3(0, 1, 0));
  const LabelledFrame f = renderer.render_free_camera(T);
  for (int i = 0; i < n; ++i) {
    double u = 0, v = 0;
    ASSERT_TRUE(K.project(T.inverse() * Vec3(-0.25 + 0.1 * i, 0.6, 0), &u, &v));
    const int x = static_cast<int>(u), y = static_cast<int>(v);
    const GeomLabel& expected = scene.labels.at("box" + std::to_string(i));
    EXPECT_EQ(f.class_id.at(x, y), expected.class_id) << "box " << i;
    EXPECT_EQ(f.instance.at(x, y), expected.instance_id) << "box " << i;
    EXPECT_NEAR(f.depth_m.at(x, y), 0.57, 1e-3);
  }
  double u = 0, v = 0;
  ASSERT_TRUE(K.project(T.inverse() * Vec3(0, 1.79, 0.3), &u, &v));
  EXPECT_EQ(f.class_id.at(static_cast<int>(u), static_cast<int>(v)), 1);
  EXPECT_EQ(f.depth_m.at(static_cast<int>(u), static_cast<int>(v)), 0.f);  // beyond 1.0 m
  EXPECT_EQ(f.class_id.at(5, 5), 0);                                        // empty sky
  EXPECT_EQ(f.instance.at(5, 5), kNoInstance);
  Pose bad = T;
  bad.translation().x() = std::nan("");
  EXPECT_THROW(renderer.render_free_camera(bad), InputError);
}

TEST(Renderer, DepthNoiseIsSeededAndScalesWithDepthSquared) {
  SceneDescription scene;
  scene.mjcf = scene_xml("<geom name=\"wall\" type=\"box\" size=\"2 0.01 2\" pos=\"0 0.81 0\"/>");
  Simulator sim(scene);
  CameraIntrinsics K;
  K.depth_noise_k = 0.01;
  const Pose T = look(Vec3(0, 0, 0), Vec3(0, 1, 0));
  RenderOptions ro;
  ro.noise_seed = 5;
  Renderer a(sim, K, ro), b(sim, K, ro);
  const LabelledFrame fa = a.render_free_camera(T), fb = b.render_free_camera(T);
  EXPECT_EQ(fa.depth_m.data, fb.depth_m.data);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int y = 150; y < 250; ++y)
    for (int x = 150; x < 250; ++x) {
      const double e = fa.depth_m.at(x, y) - 0.8;
      sum += e;
      sum2 += e * e;
      ++n;
    }
  const double sigma = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(sigma, 0.01 * 0.8 * 0.8, 0.1 * 0.0064);
}

}  // namespace
}  // namespace canopy::sim

namespace canopy::sim {
namespace {

// Renderers on two threads (one Simulator each) must neither crash nor disturb each other:
// every frame equals the same frame rendered alone.
TEST(Renderer, TwoThreadsRenderTheSameFramesAsOne) {
  world::WorldSpec spec;
  spec.rows.rows = 1;
  spec.rows.plants_per_row = 2;
  const world::World w = world::generate_world(spec);
  std::vector<Pose> views;
  for (int i = 0; i < 24; ++i)
    views.push_back(look_at(Vec3(0.02 * i, 0.3, 0.5 + 0.02 * i), Vec3(0.25, 0.75, 0.6)));
  auto render_all = [&](std::vector<LabelledFrame>* out) {
    Simulator sim(w, default_robot_config());
    Renderer renderer(sim, spec.camera);
    for (const Pose& T : views) out->push_back(renderer.render_free_camera(T));
  };
  std::vector<LabelledFrame> alone, a, b;
  render_all(&alone);
  std::thread ta(render_all, &a), tb(render_all, &b);
  ta.join();
  tb.join();
  ASSERT_EQ(a.size(), views.size());
  ASSERT_EQ(b.size(), views.size());
  for (size_t i = 0; i < views.size(); ++i)
    for (const auto* f : {&a[i], &b[i]}) {
      EXPECT_EQ(f->depth_m.data, alone[i].depth_m.data) << i;
      EXPECT_EQ(f->class_id.data, alone[i].class_id.data) << i;
      EXPECT_EQ(f->instance.data, alone[i].instance.data) << i;
      EXPECT_EQ(f->rgb.data, alone[i].rgb.data) << i;
    }
}

// The rendered model per section (issue 49): a model built again for the base's new window
// renders as one built for that window from the start, and, within the camera's range, as the
// whole row (beyond it the depth is no return in both; RGB there shows the missing plants).
TEST(Renderer, AWindowBuiltAgainRendersAsAFreshOneAndAsTheWholeRowInRange) {
  world::WorldSpec spec;
  spec.rows.rows = 1;
  spec.rows.plants_per_row = 40;
  const world::World w = world::generate_world(spec);
  world::World w_at_12 = w;
  w_at_12.spec.robot_start = BasePose{12.0, 0.0, 0.0};
  SceneOptions o;
  o.plant_window_m = 6.0;
  o.plant_section_m = 3.0;
  o.plant_reach_m = 0.5;
  o.plant_window_min_triangles = 0.0;
  const RobotConfig cfg = default_robot_config();
  SceneOptions whole_merged;  // a window's parts are merged (SceneOptions::merge_plant_parts)
  whole_merged.merge_plant_parts = true;
  Simulator moved(w, cfg, o), fresh(w_at_12, cfg, o), whole(w, cfg, whole_merged);
  Renderer moved_renderer(moved, spec.camera);  // made before the move: it follows the model
  const LabelledFrame before = moved_renderer.render_free_camera(look_at(Vec3(1.0, 0.2, 0.6), Vec3(1.2, 0.75, 0.6)));
  EXPECT_GT(std::count(before.class_id.data.begin(), before.class_id.data.end(), 0), 0);
  ArmConfig q = cfg.home;
  q[0] += 0.3;
  for (Simulator* sim : {&moved, &fresh, &whole}) sim->set_robot_state(BasePose{12.0, 0.0, 0.0}, q);
  ASSERT_TRUE(moved.show_plants_near(12.0, 12.0));
  ASSERT_EQ(moved.plant_window(), fresh.plant_window());
  Renderer fresh_renderer(fresh, spec.camera), whole_renderer(whole, spec.camera);
  const LabelledFrame a = moved_renderer.render_wrist_camera(), b = fresh_renderer.render_wrist_camera();
  EXPECT_EQ(a.rgb.data, b.rgb.data);
  EXPECT_EQ(a.depth_m.data, b.depth_m.data);
  EXPECT_EQ(a.class_id.data, b.class_id.data);
  EXPECT_EQ(a.instance.data, b.instance.data);
  int compared = 0, plant_pixels = 0;
  for (int i = 0; i < 6; ++i) {
    const Pose T = look_at(Vec3(11.4 + 0.25 * i, 0.25, 0.4 + 0.1 * i), Vec3(11.6 + 0.2 * i, 0.75, 0.7));
    const LabelledFrame m = moved_renderer.render_free_camera(T), f = fresh_renderer.render_free_camera(T),
                        full = whole_renderer.render_free_camera(T);
    EXPECT_EQ(m.rgb.data, f.rgb.data) << i;
    EXPECT_EQ(m.depth_m.data, f.depth_m.data) << i;
    EXPECT_EQ(m.class_id.data, f.class_id.data) << i;
    EXPECT_EQ(m.depth_m.data, full.depth_m.data) << i;
    for (std::size_t p = 0; p < m.depth_m.data.size(); ++p) {
      if (!(m.depth_m.data[p] > 0.f)) continue;
      ++compared;
      plant_pixels += m.class_id.data[p] == spec.class_of("leaf");
      EXPECT_EQ(m.class_id.data[p], full.class_id.data[p]);
      EXPECT_EQ(m.instance.data[p], full.instance.data[p]);
    }
  }
  EXPECT_GT(plant_pixels, 1000);
  EXPECT_GT(compared, plant_pixels);
}

// Merged plant parts (SceneOptions::merge_plant_parts, a window's): about half the meshes of the
// default preset's plants, and the same picture: every pixel's class and fruit instance, its
// depth within 0.1 mm and its colour within one level, but for a few pixels on edges (vertices
// re-centred per mesh in floats move an edge by a rounding).
TEST(Renderer, MergedPlantPartsRenderTheSameClassesDepthsAndColours) {
  world::WorldSpec spec;
  spec.rows.rows = 1;
  spec.rows.plants_per_row = 3;
  const world::World w = world::generate_world(spec);
  const RobotConfig cfg = default_robot_config();
  SceneOptions merged;
  merged.merge_plant_parts = true;
  const robot::RobotDescription robot = robot::RobotDescription::load_urdf(cfg.urdf_path);
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  const std::string plain_text = make_scene_mjcf(w, robot, cfg).mjcf, merged_text = make_scene_mjcf(w, robot, cfg, merged).mjcf;
  std::size_t parts = 0;
  for (const auto& plant : w.plants) parts += plant.parts.size();
  EXPECT_EQ(count(plain_text, "<mesh name="), parts);
  EXPECT_LT(count(merged_text, "<mesh name="), parts * 6 / 10);
  EXPECT_EQ(count(merged_text, "<mesh name="), count(merged_text, "type=\"mesh\""));
  Simulator plain_sim(w, cfg), merged_sim(w, cfg, merged);
  Renderer plain(plain_sim, spec.camera), merged_renderer(merged_sim, spec.camera);
  std::size_t pixels = 0, plant = 0, fruit = 0, off = 0;
  for (int i = 0; i < 4; ++i) {
    const Pose T = look_at(Vec3(-0.2 + 0.4 * i, 0.1, 0.5 + 0.15 * i), Vec3(0.1 + 0.3 * i, 0.75, 0.6 + 0.1 * i));
    const LabelledFrame a = plain.render_free_camera(T), b = merged_renderer.render_free_camera(T);
    for (std::size_t p = 0; p < a.depth_m.data.size(); ++p) {
      ++pixels;
      const bool same = a.class_id.data[p] == b.class_id.data[p] && a.instance.data[p] == b.instance.data[p] &&
                        std::abs(a.depth_m.data[p] - b.depth_m.data[p]) <= 1e-4f &&
                        std::abs(int(a.rgb.data[p].r) - int(b.rgb.data[p].r)) <= 1 &&
                        std::abs(int(a.rgb.data[p].g) - int(b.rgb.data[p].g)) <= 1 &&
                        std::abs(int(a.rgb.data[p].b) - int(b.rgb.data[p].b)) <= 1;
      off += !same;
      plant += a.class_id.data[p] == spec.class_of("leaf") || a.class_id.data[p] == spec.class_of("petiole") ||
               a.class_id.data[p] == spec.class_of("stem");
      fruit += a.instance.data[p] != kNoInstance;
    }
  }
  EXPECT_GT(plant, pixels / 10);
  EXPECT_GT(fruit, 100u);
  EXPECT_LE(off, pixels / 1000) << off << " of " << pixels << " pixels differ";
}

}  // namespace
}  // namespace canopy::sim
