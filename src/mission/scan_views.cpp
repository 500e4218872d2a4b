#include "canopy/mission/scan_views.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/world/world_spec.h"

namespace canopy::mission {

std::vector<double> stop_positions(const settings::StopParams& params, const world::WorldSpec& world) {
  if (!params.positions_m.empty()) return params.positions_m;
  const double first = world.rows.x_start_m;
  const double last = world.rows.x_start_m + (world.rows.plants_per_row - 1) * world.rows.plant_spacing_m;
  std::vector<double> out;
  if (last - first < 1e-9) return {first};  // one plant per row: one stop
  for (int k = 0; k < params.count; ++k)
    out.push_back(params.count == 1 ? 0.5 * (first + last) : first + (last - first) * k / (params.count - 1));
  return out;
}

ScanView scan_view(const settings::ScanParams& params, const Pose& T_base_arm, double lateral_m, double height_m,
                   double azimuth_deg) {
  const Vec3 arm = T_base_arm.translation();
  const double side = lateral_m >= 0.0 ? 1.0 : -1.0;  // the camera sits on the aisle side of its target
  const Vec3 target(arm.x() + params.along_m, lateral_m, height_m);
  const double a = azimuth_deg * M_PI / 180.0;
  const Vec3 dir(std::sin(a) * side, -side * std::cos(a), 0.0);  // from target towards the camera
  return {look_at(target + params.distance_m * dir, target), lateral_m, height_m, azimuth_deg};
}

std::vector<ScanView> scan_view_list(const settings::ScanParams& params, const world::WorldSpec& world, const Pose& T_base_arm,
                                     bool extra) {
  std::vector<double> lateral = params.lateral_m;
  if (lateral.empty()) {
    lateral.push_back(world.rows.row_offset_m);
    if (world.rows.rows > 1) lateral.push_back(-world.rows.row_offset_m);
  }
  const std::vector<double>& heights = extra ? params.extra_heights_m : params.heights_m;
  std::vector<ScanView> views;
  for (double y : lateral)
    for (double h : heights)
      for (double a_deg : params.azimuths_deg) views.push_back(scan_view(params, T_base_arm, y, h, a_deg));
  return views;
}

std::vector<Pose> scan_views_in_base(const settings::ScanParams& params, const world::WorldSpec& world, const Pose& T_base_arm,
                                     bool extra) {
  std::vector<Pose> out;
  for (const ScanView& v : scan_view_list(params, world, T_base_arm, extra)) out.push_back(v.T_base_camera);
  return out;
}

namespace {
double rotation_angle(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle();
}
}  // namespace

std::vector<ScanView> scan_replacements(const settings::ScanParams& params, const Pose& T_base_arm, const ScanView& failed) {
  struct Scored {
    double cost;
    std::size_t order;
    ScanView view;
  };
  std::vector<Scored> out;
  const int n = params.replace_steps;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      if (i == 0 && j == 0) continue;
      const double h = failed.height_m + i * params.replace_height_step_m;
      const double a = failed.azimuth_deg + j * params.replace_azimuth_step_deg;
      if (h <= 0.0 || a <= -90.0 || a >= 90.0) continue;
      const ScanView v = scan_view(params, T_base_arm, failed.lateral_m, h, a);
      const double cost = (v.T_base_camera.translation() - failed.T_base_camera.translation()).norm() +
                          params.distance_m * rotation_angle(v.T_base_camera, failed.T_base_camera);
      out.push_back({cost, out.size(), v});
    }
  std::stable_sort(out.begin(), out.end(), [](const Scored& x, const Scored& y) { return x.cost < y.cost; });
  std::vector<ScanView> views;
  for (const Scored& s : out) views.push_back(s.view);
  return views;
}

}  // namespace canopy::mission
