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

}  // namespace
}  // namespace canopy::sim
