#include "canopy/mission/mission_params.h"

#include <cmath>

#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/world/world_spec.h"

namespace canopy::mission {

namespace {

std::vector<double> list(YamlReader& y, const std::string& key, const std::vector<double>& fallback) {
  const std::vector<double> v = y.get(key, fallback);
  for (double x : v) y.check(std::isfinite(x), key, "must hold finite numbers");
  return v;
}

}  // namespace

MissionParams MissionParams::from_yaml(YamlReader& y) {
  MissionParams p;
  {
    YamlReader c = y.child("stops");
    auto& q = p.stops;
    q.count = get_count(c, "count", q.count, 1, 1000);
    q.positions_m = list(c, "positions_m", q.positions_m);
    q.base_y_m = get_finite(c, "base_y_m", q.base_y_m);
    q.timeout_s = get_positive(c, "timeout_s", q.timeout_s);
    c.finish();
  }
  {
    YamlReader c = y.child("scan");
    auto& q = p.scan;
    q.distance_m = get_positive(c, "distance_m", q.distance_m);
    q.azimuths_deg = list(c, "azimuths_deg", q.azimuths_deg);
    q.heights_m = list(c, "heights_m", q.heights_m);
    q.extra_heights_m = list(c, "extra_heights_m", q.extra_heights_m);
    q.lateral_m = list(c, "lateral_m", q.lateral_m);
    q.along_m = get_finite(c, "along_m", q.along_m);
    c.check(!q.azimuths_deg.empty(), "azimuths_deg", "needs at least one azimuth");
    for (double a : q.azimuths_deg) c.check(std::abs(a) < 90.0, "azimuths_deg", "must lie in (-90, 90) degrees");
    c.finish();
  }
  {
    YamlReader c = y.child("loop");
    auto& q = p.loop;
    q.views_per_stop = get_count(c, "views_per_stop", q.views_per_stop, 0, 10000);
    q.max_rounds = get_count(c, "max_rounds", q.max_rounds, 0, 10000);
    q.max_attempts = get_count(c, "max_attempts", q.max_attempts, 0, 100000);
    q.region_half_length_m = get_positive(c, "region_half_length_m", q.region_half_length_m);
    q.region_half_width_m = get_positive(c, "region_half_width_m", q.region_half_width_m);
    q.region_min_z_m = get_finite(c, "region_min_z_m", q.region_min_z_m);
    q.region_max_z_m = get_finite(c, "region_max_z_m", q.region_max_z_m);
    c.check(q.region_max_z_m > q.region_min_z_m, "region_max_z_m", "must be above region_min_z_m");
    c.finish();
  }
  {
    YamlReader c = y.child("record");
    auto& q = p.record;
    q.truth_voxel_m = get_positive(c, "truth_voxel_m", q.truth_voxel_m);
    c.check(q.truth_voxel_m >= 0.002 && q.truth_voxel_m <= 0.2, "truth_voxel_m", "must be in [0.002, 0.2] m");
    q.base_check_period_s = get_positive(c, "base_check_period_s", q.base_check_period_s);
    q.metrics_every_view = c.get("metrics_every_view", q.metrics_every_view);
    c.finish();
  }
  return p;
}

YAML::Node MissionParams::to_yaml() const {
  YAML::Node n;
  auto seq = [](const std::vector<double>& v) {
    YAML::Node s(YAML::NodeType::Sequence);
    for (double x : v) s.push_back(x);
    return s;
  };
  n["stops"]["count"] = stops.count;
  n["stops"]["positions_m"] = seq(stops.positions_m);
  n["stops"]["base_y_m"] = stops.base_y_m;
  n["stops"]["timeout_s"] = stops.timeout_s;
  n["scan"]["distance_m"] = scan.distance_m;
  n["scan"]["azimuths_deg"] = seq(scan.azimuths_deg);
  n["scan"]["heights_m"] = seq(scan.heights_m);
  n["scan"]["extra_heights_m"] = seq(scan.extra_heights_m);
  n["scan"]["lateral_m"] = seq(scan.lateral_m);
  n["scan"]["along_m"] = scan.along_m;
  n["loop"]["views_per_stop"] = loop.views_per_stop;
  n["loop"]["max_rounds"] = loop.max_rounds;
  n["loop"]["max_attempts"] = loop.max_attempts;
  n["loop"]["region_half_length_m"] = loop.region_half_length_m;
  n["loop"]["region_half_width_m"] = loop.region_half_width_m;
  n["loop"]["region_min_z_m"] = loop.region_min_z_m;
  n["loop"]["region_max_z_m"] = loop.region_max_z_m;
  n["record"]["truth_voxel_m"] = record.truth_voxel_m;
  n["record"]["base_check_period_s"] = record.base_check_period_s;
  n["record"]["metrics_every_view"] = record.metrics_every_view;
  return n;
}

bool MissionParams::operator==(const MissionParams& o) const {
  return stops.count == o.stops.count && stops.positions_m == o.stops.positions_m && stops.base_y_m == o.stops.base_y_m &&
         stops.timeout_s == o.stops.timeout_s && scan.distance_m == o.scan.distance_m &&
         scan.azimuths_deg == o.scan.azimuths_deg && scan.heights_m == o.scan.heights_m &&
         scan.extra_heights_m == o.scan.extra_heights_m && scan.lateral_m == o.scan.lateral_m &&
         scan.along_m == o.scan.along_m && loop.views_per_stop == o.loop.views_per_stop &&
         loop.max_rounds == o.loop.max_rounds && loop.max_attempts == o.loop.max_attempts &&
         loop.region_half_length_m == o.loop.region_half_length_m &&
         loop.region_half_width_m == o.loop.region_half_width_m && loop.region_min_z_m == o.loop.region_min_z_m &&
         loop.region_max_z_m == o.loop.region_max_z_m && record.truth_voxel_m == o.record.truth_voxel_m &&
         record.base_check_period_s == o.record.base_check_period_s &&
         record.metrics_every_view == o.record.metrics_every_view;
}

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
