#include "canopy/sim/scene_mjcf.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>

#include "canopy/robot/robot_config.h"
#include "canopy/world/world.h"

namespace canopy::sim {
namespace {

// The numbers of attribute `attr` of the element that starts at `pos` in `xml`.
std::vector<double> attribute_numbers(const std::string& xml, std::size_t pos, const std::string& attr) {
  const std::size_t start = xml.find(attr + "=\"", pos);
  EXPECT_NE(start, std::string::npos);
  const std::size_t begin = start + attr.size() + 2;
  std::istringstream in(xml.substr(begin, xml.find('"', begin) - begin));
  std::vector<double> out;
  for (std::string token; in >> token;) out.push_back(std::strtod(token.c_str(), nullptr));
  return out;
}

TEST(SceneMjcf, MeshVerticesAreWrittenAtFullPrecision) {
  const RobotConfig cfg = default_robot_config();
  const robot::RobotDescription robot = robot::RobotDescription::load_urdf(cfg.urdf_path);
  world::WorldSpec spec;
  spec.rows.plants_per_row = 1;
  spec.rows.x_start_m = 1.0 / 3.0;  // no short decimal form
  world::World w = world::generate_world(spec);
  // A vertex far from the origin and one very close to it: fixed-point formats truncate
  // the first and round the second to zero.
  world::TriMesh& mesh = w.plants[0].parts[0].mesh;
  mesh.vertices[0] = Vec3(123456789.123456789, -987654321.0 / 7.0, 1e-9 / 3.0);
  const std::string xml = make_scene_mjcf(w, robot, cfg).mjcf;
  int checked_meshes = 0;
  for (const auto& plant : w.plants)
    for (const auto& part : plant.parts) {
      const std::size_t at = xml.find("<mesh name=\"" + part.name + "\"");
      ASSERT_NE(at, std::string::npos) << part.name;
      const std::vector<double> v = attribute_numbers(xml, at, "vertex");
      ASSERT_EQ(v.size(), 3 * part.mesh.vertices.size()) << part.name;
      for (std::size_t i = 0; i < part.mesh.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k) ASSERT_EQ(v[3 * i + k], part.mesh.vertices[i][k]) << part.name << " vertex " << i;
      ++checked_meshes;
    }
  EXPECT_GT(checked_meshes, 20);
}


// Heating pipes: a pair along every row at the height and offsets the world file gives, from
// half a spacing before the first plant to half a spacing after the last, labelled as ground.
TEST(SceneMjcf, HeatingPipesRunAlongEveryRowEachSideOfItsCentreLine) {
  const RobotConfig cfg = default_robot_config();
  const robot::RobotDescription robot = robot::RobotDescription::load_urdf(cfg.urdf_path);
  world::WorldSpec spec;
  spec.rows.plants_per_row = 2;
  spec.rows.plant_spacing_m = 0.4;
  spec.rows.x_start_m = 0.5;
  spec.rows.row_offset_m = 0.8;
  spec.ground.heating_pipes = true;
  spec.ground.pipe_offset_m = 0.2;
  spec.ground.pipe_height_m = 0.1;
  spec.ground.pipe_diameter_m = 0.05;
  const world::World w = world::generate_world(spec);
  const SceneDescription scene = make_scene_mjcf(w, robot, cfg);
  const double expected_y[2][2] = {{0.6, 1.0}, {-1.0, -0.6}};
  for (int row = 0; row < 2; ++row)
    for (int side = 0; side < 2; ++side) {
      const std::string name = "heating_pipe_" + std::to_string(row) + "_" + std::to_string(side);
      const std::size_t at = scene.mjcf.find("<geom name=\"" + name + "\"");
      ASSERT_NE(at, std::string::npos) << name;
      const std::vector<double> ft = attribute_numbers(scene.mjcf, at, "fromto");
      ASSERT_EQ(ft.size(), 6u) << name;
      EXPECT_NEAR(ft[0], 0.3, 1e-12) << name;  // x_start - spacing / 2
      EXPECT_NEAR(ft[3], 1.1, 1e-12) << name;  // last plant + spacing / 2
      EXPECT_NEAR(ft[1], expected_y[row][side], 1e-12) << name;
      EXPECT_EQ(ft[1], ft[4]) << name;
      EXPECT_EQ(ft[2], 0.1) << name;
      EXPECT_EQ(ft[5], 0.1) << name;
      EXPECT_EQ(attribute_numbers(scene.mjcf, at, "size").at(0), 0.025) << name;
      ASSERT_EQ(scene.labels.count(name), 1u) << name;
      EXPECT_EQ(scene.labels.at(name).class_id, spec.class_of("ground")) << name;
    }
  EXPECT_EQ(scene.mjcf.find("heating_pipe_0_2"), std::string::npos);
  // Off by default: the scene has none.
  world::WorldSpec plain = spec;
  plain.ground.heating_pipes = false;
  EXPECT_EQ(make_scene_mjcf(world::generate_world(plain), robot, cfg).mjcf.find("heating_pipe_"), std::string::npos);
}

// A window of plants (issue 49): only the plants whose base lies in it, each with all its
// parts and labels; the ground plane centred on it. Unbounded, the scene is the one always made.
TEST(SceneMjcf, AWindowHoldsItsPlantsOnlyAndNoWindowIsTodaysScene) {
  const RobotConfig cfg = default_robot_config();
  const robot::RobotDescription robot = robot::RobotDescription::load_urdf(cfg.urdf_path);
  world::WorldSpec spec;
  spec.rows.plants_per_row = 8;
  const world::World w = world::generate_world(spec);
  SceneOptions unbounded;
  unbounded.plant_window_m = 12.0;  // the window's length alone changes no scene text
  EXPECT_EQ(make_scene_mjcf(w, robot, cfg, unbounded).mjcf, make_scene_mjcf(w, robot, cfg).mjcf);
  EXPECT_NE(make_scene_mjcf(w, robot, cfg).mjcf.find("<geom name=\"ground\" type=\"plane\" size=\"30 30 0.1\" material"),
            std::string::npos);
  SceneOptions window;
  window.plants_from_x_m = 1.0;
  window.plants_to_x_m = 2.5;
  const SceneDescription scene = make_scene_mjcf(w, robot, cfg, window);
  int inside = 0;
  for (const auto& plant : w.plants) {
    const bool in = plant.base_position.x() >= 1.0 && plant.base_position.x() < 2.5;
    inside += in;
    for (const auto& part : plant.parts) {
      EXPECT_EQ(scene.labels.count(part.name), in ? 1u : 0u) << part.name;
      EXPECT_EQ(scene.mjcf.find("<mesh name=\"" + part.name + "\"") != std::string::npos, in) << part.name;
      EXPECT_EQ(scene.mjcf.find("<geom name=\"" + part.name + "\"") != std::string::npos, in) << part.name;
    }
  }
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, static_cast<int>(w.plants.size()));
  EXPECT_NE(scene.mjcf.find("<geom name=\"ground\" type=\"plane\" size=\"30 30 0.1\" pos=\"1.75 0 0\""), std::string::npos);
  EXPECT_TRUE(scene.labels.count("ground"));
}

// A world that does not hold its plants (issue 49: a long world's plants are generated when a
// window needs them) writes the same scene, whole or a window, as the world that holds them.
TEST(SceneMjcf, AWorldThatDropsItsPlantsWritesTheSameScene) {
  const RobotConfig cfg = default_robot_config();
  const robot::RobotDescription robot = robot::RobotDescription::load_urdf(cfg.urdf_path);
  world::WorldSpec spec;
  spec.rows.plants_per_row = 6;
  world::GenerateOptions drop;
  drop.drop_plants_from_triangles = 0.0;
  const world::World held = world::generate_world(spec), dropped = world::generate_world(spec, drop);
  ASSERT_FALSE(dropped.plants_held());
  SceneOptions window;
  window.plants_from_x_m = 1.0;
  window.plants_to_x_m = 2.5;
  for (const SceneOptions& o : {SceneOptions{}, window}) {
    const SceneDescription a = make_scene_mjcf(held, robot, cfg, o), b = make_scene_mjcf(dropped, robot, cfg, o);
    EXPECT_GT(a.mjcf.size(), 100000u);
    EXPECT_TRUE(a.mjcf == b.mjcf);
    ASSERT_EQ(a.labels.size(), b.labels.size());
    for (const auto& [name, label] : a.labels) {
      ASSERT_TRUE(b.labels.count(name)) << name;
      EXPECT_EQ(b.labels.at(name).class_id, label.class_id) << name;
      EXPECT_EQ(b.labels.at(name).instance_id, label.instance_id) << name;
    }
    EXPECT_EQ(a.files, b.files);
  }
}

}  // namespace
}  // namespace canopy::sim
