// An imported plant in MuJoCo 2.2.2: its folder's OBJ meshes load as static worldbody geoms
// and render with the right class and instance labels, alone and placed in a world with the
// robot next to procedural plants.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/perception/color_segmentation.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/plant_import.h"
#include "canopy/world/world.h"
#include "../world/plant_files.h"

namespace canopy::sim {
namespace {

namespace fs = std::filesystem;
using namespace canopy::test_plant;

// The test plant (fruit B unripe) imported and saved; returns the folder.
std::string saved_plant(const std::string& name) {
  const std::string dir = testing::TempDir() + "/imported_plant_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir + "/src");
  write_text(dir + "/src/plant.dae", collada(true, true));
  world::ImportOptions o;
  o.rules = world::class_preset("capsicum");
  world::import_plant(dir + "/src/plant.dae", o).save(dir + "/plant");
  return dir + "/plant";
}

std::map<int, int> count(const Image<std::int32_t>& img) {
  std::map<int, int> n;
  for (int v = 0; v < img.height; ++v)
    for (int u = 0; u < img.width; ++u) ++n[img.at(u, v)];
  return n;
}

TEST(ImportedPlant, ObjMeshesLoadInMuJoCoAndRenderWithTheirLabels) {
  const std::string dir = saved_plant("obj");
  const world::PlantAsset asset = world::load_plant_asset(dir);
  const SemanticClasses classes;
  // The folder's own OBJ files, by file name, as static worldbody geoms.
  const YAML::Node parts = YAML::LoadFile(dir + "/plant.yaml")["parts"];
  SceneDescription scene;
  std::string assets, bodies;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string name = "part" + std::to_string(i);
    const int fruit = parts[i]["fruit"] ? parts[i]["fruit"].as<int>() : -1;
    assets += "<mesh name=\"" + name + "\" file=\"" + dir + "/" + parts[i]["file"].as<std::string>() + "\"/>";
    bodies += "<geom name=\"" + name + "\" type=\"mesh\" mesh=\"" + name + "\" contype=\"0\" conaffinity=\"0\"/>";
    scene.labels[name] = GeomLabel{classes.index_of(parts[i]["class"].as<std::string>()), fruit, false};
  }
  scene.mjcf = "<mujoco><statistic extent=\"2\" center=\"0 0 0.5\"/><visual><map znear=\"0.01\" zfar=\"10\"/>"
               "<quality offsamples=\"0\"/></visual><asset>" + assets + "</asset><worldbody>" + bodies +
               "</worldbody></mujoco>";
  Simulator sim(scene);
  CameraIntrinsics K;
  K.max_range_m = 3.0;
  Renderer renderer(sim, K);
  // From 1 m in front (-y), level with the fruits, looking along +y.
  const Vec3 eye(0.0, -1.0, 0.57);
  const LabelledFrame f = renderer.render_free_camera(look_at(eye, eye + Vec3(0, 1, 0)));
  const auto instances = count(f.instance);
  EXPECT_GT(instances.count(0) ? instances.at(0) : 0, 500);  // fruit B (unripe, still labelled)
  EXPECT_GT(instances.count(1) ? instances.at(1) : 0, 500);  // fruit A
  int leaf = 0, fruit = 0;
  for (int v = 0; v < f.class_id.height; ++v)
    for (int u = 0; u < f.class_id.width; ++u) {
      leaf += f.class_id.at(u, v) == classes.index_of("leaf");
      fruit += f.class_id.at(u, v) == classes.index_of("fruit");
      if (f.instance.at(u, v) != kNoInstance) {
        ASSERT_EQ(f.class_id.at(u, v), classes.index_of("fruit"));
      }
    }
  EXPECT_GT(leaf, 100);
  EXPECT_GT(fruit, 1000);
  // Depth at fruit B's centre: its front face, half a side in front of its centre.
  const world::FruitTruth& b = asset.truth.fruits[0];
  const Vec3 c_cam = f.T_world_camera.inverse() * b.center;
  const double u = K.fx_px * c_cam.x() / c_cam.z() + K.cx_px, v = K.fy_px * c_cam.y() / c_cam.z() + K.cy_px;
  EXPECT_NEAR(f.depth_m.at(static_cast<int>(u), static_cast<int>(v)), 1.0 - 0.5 * kFruitSideIn * kInch, 2e-3);
  EXPECT_EQ(f.instance.at(static_cast<int>(u), static_cast<int>(v)), 0);
}

TEST(ImportedPlant, PlacedInAWorldItRendersNextToProceduralPlantsWithWorldInstanceIds) {
  const std::string dir = saved_plant("world");
  const std::string world_file = testing::TempDir() + "/imported_plant_world.yaml";
  write_text(world_file, "name: mixed\nseed: 3\nrows: {rows: 2, plants_per_row: 1, position_jitter_m: 0.0}\n"
                         "plants: [{plant: {import: " + dir + "}, slot: [0, 0], yaw_deg: 0}]\n");
  const world::World w = world::generate_world(world::WorldSpec::load(world_file));
  ASSERT_EQ(w.plants.size(), 2u);
  ASSERT_FALSE(w.plants[0].import_dir.empty());
  std::vector<int> imported_ids;
  for (const auto& part : w.plants[0].parts)
    if (part.instance_id != kNoInstance) imported_ids.push_back(part.instance_id);
  ASSERT_EQ(imported_ids.size(), 2u);
  Simulator sim(w, default_robot_config());
  Renderer renderer(sim, w.spec.camera);
  // From the aisle, 0.75 m in front of the imported plant (row at y = +0.75).
  const Vec3 eye(0.0, 0.0, 0.57);
  const LabelledFrame f = renderer.render_free_camera(look_at(eye, eye + Vec3(0, 1, 0)));
  const auto instances = count(f.instance);
  for (int id : imported_ids) EXPECT_GT(instances.count(id) ? instances.at(id) : 0, 200) << "instance " << id;
  for (const auto& [id, n] : instances) {  // nothing else but these two and background
    if (id != kNoInstance) {
      EXPECT_TRUE(id == imported_ids[0] || id == imported_ids[1]) << id;
    }
  }
  // The world's ground truth holds the imported fruits with their ripeness.
  int targets = 0;
  for (const auto& t : w.truth.fruits)
    if (t.plant_index == 0) targets += t.target;
  EXPECT_EQ(targets, 1);
}


// The textured test plant (white diffuse colours; TGA textures: fruit red where their UVs
// point, blue elsewhere; leaves green) imported with `mode`, placed in a world and seen from
// the aisle: the fruit render red (not blue: the texture is not flipped) and colour
// segmentation labels them fruit.
void expect_textured_fruit_red(world::TextureMode mode, const std::string& name) {
  const std::string dir = testing::TempDir() + "/textured_plant_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir + "/src");
  write_text(dir + "/src/plant.dae", collada_textured(true));
  write_tga(dir + "/src/Capsicum_frt1.tga", 8, 8, 4, {200, 30, 20}, {20, 30, 200});
  write_tga(dir + "/src/Capsicum_frt0.tga", 8, 8, 4, {200, 200, 40}, {20, 30, 200});
  write_tga(dir + "/src/Capsicum_lef.tga", 8, 8, 8, {40, 160, 40}, {40, 160, 40});
  world::ImportOptions o;
  o.rules = world::class_preset("capsicum");
  o.texture = mode;
  world::import_plant(dir + "/src/plant.dae", o).save(dir + "/plant");
  write_text(dir + "/w.yaml", "name: textured\nseed: 3\nrows: {rows: 1, plants_per_row: 1, position_jitter_m: 0.0}\n"
                              "plants: [{plant: {import: " + dir + "/plant}, slot: [0, 0], yaw_deg: 0}]\n");
  const world::World w = world::generate_world(world::WorldSpec::load(dir + "/w.yaml"));
  Simulator sim(w, default_robot_config());
  Renderer renderer(sim, w.spec.camera);
  const Vec3 eye(0.0, 0.0, 0.57);
  const LabelledFrame f = renderer.render_free_camera(look_at(eye, eye + Vec3(0, 1, 0)));
  const Image<std::uint8_t> seg = perception::segment_by_color(f.rgb, {}, w.spec.classes);
  int target = -1;
  for (const auto& part : w.plants[0].parts)
    if (part.instance_id != kNoInstance && part.fruit_target) target = part.instance_id;
  long n = 0, red = 0, as_fruit = 0, leaf_px = 0, leaf_as_leaf = 0;
  for (int v = 0; v < f.rgb.height; ++v)
    for (int u = 0; u < f.rgb.width; ++u) {
      const Rgb8 c = f.rgb.at(u, v);
      if (f.instance.at(u, v) == target) {
        ++n;
        red += c.r > 2 * c.g && c.r > 2 * c.b;
        as_fruit += seg.at(u, v) == w.spec.classes.index_of("fruit");
      } else if (f.class_id.at(u, v) == w.spec.classes.index_of("leaf")) {
        ++leaf_px;
        leaf_as_leaf += seg.at(u, v) == w.spec.classes.index_of("leaf");
      }
    }
  ASSERT_GT(n, 200);
  EXPECT_GT(red, 0.95 * n) << red << " of " << n;
  EXPECT_GT(as_fruit, 0.95 * n) << as_fruit << " of " << n;
  ASSERT_GT(leaf_px, 50);
  EXPECT_GT(leaf_as_leaf, 0.9 * leaf_px) << leaf_as_leaf << " of " << leaf_px;
}

TEST(ImportedPlant, TexturedFruitRendersInItsTextureColourAndSegmentsAsFruit) {
  expect_textured_fruit_red(world::TextureMode::kImage, "image");
}

TEST(ImportedPlant, TextureMeanFruitRendersInTheMeanColourAndSegmentsAsFruit) {
  expect_textured_fruit_red(world::TextureMode::kMean, "mean");
}

}  // namespace
}  // namespace canopy::sim
