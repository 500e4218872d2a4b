#include "canopy/evaluation/view_presets.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"

namespace canopy::evaluation {

using namespace mapping;  // the map types this file reads

std::vector<Pose> ring_views(const world::World& world, const RingViews& ring) {
  std::vector<Pose> out;
  for (const world::Plant& p : world.plants) {
    // Start on the aisle side (the aisle runs along y = 0).
    const double a0 = p.base_position.y() > 0 ? -M_PI / 2 : M_PI / 2;
    for (double h : ring.heights) {
      const Vec3 target(p.base_position.x(), p.base_position.y(), p.base_position.z() + h * p.height_m);
      for (int k = 0; k < ring.azimuths; ++k) {
        const double a = a0 + 2.0 * M_PI * k / ring.azimuths;
        out.push_back(look_at(target + ring.radius_m * Vec3(std::cos(a), std::sin(a), 0.0), target));
      }
    }
  }
  return out;
}

std::vector<Pose> aisle_views(const world::World& world, int per_side, double distance_m, double height_m) {
  std::vector<Pose> out;
  const world::RowLayout& rows = world.spec.rows;
  const double x0 = rows.x_start_m, x1 = x0 + (rows.plants_per_row - 1) * rows.plant_spacing_m;
  for (int side = 0; side < rows.rows; ++side) {
    const double y_row = side == 0 ? rows.row_offset_m : -rows.row_offset_m;
    const double y_cam = y_row + (side == 0 ? -distance_m : distance_m);
    for (int i = 0; i < per_side; ++i) {
      const double s = per_side > 1 ? double(i) / (per_side - 1) : 0.5;
      const double x = x0 + s * (x1 - x0);
      out.push_back(look_at(Vec3(x, y_cam, height_m), Vec3(x, y_row, height_m)));
    }
  }
  return out;
}

std::vector<Pose> load_views(const std::string& path) {
  std::istringstream in(read_file(path));
  std::vector<Pose> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::string csv;
    std::istringstream words(line);
    for (std::string w; words >> w;) csv += (csv.empty() ? "" : ",") + w;
    while (csv.find(",,") != std::string::npos) csv.replace(csv.find(",,"), 2, ",");
    if (csv.empty()) continue;
    out.push_back(parse_pose7(csv, path + ":" + std::to_string(n)));
  }
  if (out.empty()) throw InputError(path + ": no camera poses (expected lines 'x y z qw qx qy qz')");
  return out;
}

std::vector<Pose> views_from_spec(const std::string& spec, const world::World& world) {
  if (spec == "ring") return ring_views(world);
  if (spec == "aisle") return aisle_views(world);
  return load_views(spec);
}

}  // namespace canopy::evaluation
