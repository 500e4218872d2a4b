#include "canopy/mission/mission_params.h"

#include <cmath>

#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/world/world_spec.h"

namespace canopy::mission {

std::vector<double> stop_positions(const StopParams& params, const world::WorldSpec& world) {
  if (!params.positions_m.empty()) return params.positions_m;
  const double first = world.rows.x_start_m;
  const double last = world.rows.x_start_m + (world.rows.plants_per_row - 1) * world.rows.plant_spacing_m;
  std::vector<double> out;
  if (last - first < 1e-9) return {first};  // one plant per row: one stop
  for (int k = 0; k < params.count; ++k)
    out.push_back(params.count == 1 ? 0.5 * (first + last) : first + (last - first) * k / (params.count - 1));
  return out;
}

std::vector<Pose> scan_views_in_base(const ScanParams& params, const world::WorldSpec& world, const Pose& T_base_arm,
                                     bool extra) {
  std::vector<double> lateral = params.lateral_m;
  if (lateral.empty()) {
    lateral.push_back(world.rows.row_offset_m);
    if (world.rows.rows > 1) lateral.push_back(-world.rows.row_offset_m);
  }
  const std::vector<double>& heights = extra ? params.extra_heights_m : params.heights_m;
  const Vec3 arm = T_base_arm.translation();
  std::vector<Pose> views;
  for (double y : lateral) {
    const double side = y >= 0.0 ? 1.0 : -1.0;  // the camera sits on the aisle side of its target
    for (double h : heights)
      for (double a_deg : params.azimuths_deg) {
        const Vec3 target(arm.x() + params.along_m, y, h);
        const double a = a_deg * M_PI / 180.0;
        const Vec3 dir(std::sin(a) * side, -side * std::cos(a), 0.0);  // from target towards the camera
        views.push_back(look_at(target + params.distance_m * dir, target));
      }
  }
  return views;
}

}  // namespace canopy::mission
