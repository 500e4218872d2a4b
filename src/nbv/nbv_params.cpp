#include "canopy/nbv/nbv_params.h"

#include <cmath>

#include "canopy/common/error.h"

namespace canopy::nbv {

std::string to_string(Proximity p) { return enum_name(kProximityNames, p); }

Proximity proximity_from_string(const std::string& s, const std::string& where) {
  return enum_from_name(kProximityNames, s, where, "proximity");
}



NbvParams NbvParams::from_yaml(YamlReader& y) {
  NbvParams p;
  {
    YamlReader c = y.child("cluster");
    p.cluster.min_logodds = get_finite(c, "min_logodds", p.cluster.min_logodds);
    p.cluster.epsilon_m = get_positive(c, "epsilon_m", p.cluster.epsilon_m);
    p.cluster.min_points = get_count(c, "min_points", p.cluster.min_points, 1, 1000000);
    c.finish();
  }
  {
    YamlReader c = y.child("candidates");
    auto& q = p.candidates;
    q.radius_m = get_positive(c, "radius_m", q.radius_m);
    q.polar_count = get_count(c, "polar_count", q.polar_count, 1, 1000);
    q.polar_min_deg = get_finite(c, "polar_min_deg", q.polar_min_deg);
    q.polar_max_deg = get_finite(c, "polar_max_deg", q.polar_max_deg);
    q.azimuth_count = get_count(c, "azimuth_count", q.azimuth_count, 1, 1000);
    q.min_height_m = get_finite(c, "min_height_m", q.min_height_m);
    c.check(q.polar_min_deg >= 0.0 && q.polar_min_deg <= 180.0, "polar_min_deg", "must be in [0, 180]");
    c.check(q.polar_max_deg >= q.polar_min_deg && q.polar_max_deg <= 180.0, "polar_max_deg",
            "must be in [polar_min_deg, 180]");
    c.finish();
  }
  {
    YamlReader c = y.child("rays");
    auto& q = p.rays;
    q.cluster_size_m = get_positive(c, "cluster_size_m", q.cluster_size_m);
    q.step_m = get_positive(c, "step_m", q.step_m);
    q.dense_grid = get_count(c, "dense_grid", q.dense_grid, 1, 4096);
    q.sparse_grid = get_count(c, "sparse_grid", q.sparse_grid, 1, 4096);
    q.depth_margin_m = get_finite(c, "depth_margin_m", q.depth_margin_m);
    c.check(q.depth_margin_m >= 0.0, "depth_margin_m", "must be >= 0");
    // The window grid has (cluster_size / step)^2 rays: keep it a grid, not a flood.
    c.check(q.cluster_size_m / q.step_m <= 512.0, "step_m", "is too small for cluster_size_m (more than 512 x 512 rays)");
    c.finish();
  }
  {
    YamlReader c = y.child("gain");
    auto& q = p.gain;
    q.max_dist_m = get_positive(c, "max_dist_m", q.max_dist_m);
    q.proximity = c.get_choice("proximity", q.proximity, kProximityNames);
    q.ae_stop_occupancy = get_finite(c, "ae_stop_occupancy", q.ae_stop_occupancy);
    q.unknown_low = get_finite(c, "unknown_low", q.unknown_low);
    q.unknown_high = get_finite(c, "unknown_high", q.unknown_high);
    q.uvpc_base_weight = get_finite(c, "uvpc_base_weight", q.uvpc_base_weight);
    c.check(q.ae_stop_occupancy > 0.0 && q.ae_stop_occupancy <= 1.0, "ae_stop_occupancy", "must be in (0, 1]");
    c.check(q.unknown_low >= 0.0 && q.unknown_low <= 1.0, "unknown_low", "must be in [0, 1]");
    c.check(q.unknown_high >= q.unknown_low && q.unknown_high <= 1.0, "unknown_high", "must be in [unknown_low, 1]");
    c.finish();
  }
  {
    YamlReader c = y.child("planner");
    p.planner.top_k = get_count(c, "top_k", p.planner.top_k, 1, 1000);
    c.finish();
  }
  {
    YamlReader c = y.child("views");
    auto& q = p.views;
    q.taken_position_m = get_positive(c, "taken_position_m", q.taken_position_m);
    q.taken_angle_deg = get_positive(c, "taken_angle_deg", q.taken_angle_deg);
    q.done_epsilon_m = get_positive(c, "done_epsilon_m", q.done_epsilon_m);
    c.finish();
  }
  {
    YamlReader c = y.child("frontier");
    auto& q = p.frontier;
    q.max_targets = get_count(c, "max_targets", q.max_targets, 1, 100000);
    q.min_view_distance_m = get_positive(c, "min_view_distance_m", q.min_view_distance_m);
    q.max_view_distance_m = get_positive(c, "max_view_distance_m", q.max_view_distance_m);
    q.roi_inflation_radius_m = get_positive(c, "roi_inflation_radius_m", q.roi_inflation_radius_m);
    q.roi_inflation_resolution_m = get_positive(c, "roi_inflation_resolution_m", q.roi_inflation_resolution_m);
    q.unknown_low = get_finite(c, "unknown_low", q.unknown_low);
    q.unknown_high = get_finite(c, "unknown_high", q.unknown_high);
    q.unknown_weight = get_finite(c, "unknown_weight", q.unknown_weight);
    q.roi_weight = get_finite(c, "roi_weight", q.roi_weight);
    q.distance_cost_per_m = get_finite(c, "distance_cost_per_m", q.distance_cost_per_m);
    q.roi_utility_threshold = get_finite(c, "roi_utility_threshold", q.roi_utility_threshold);
    c.check(q.max_view_distance_m >= q.min_view_distance_m, "max_view_distance_m", "must be >= min_view_distance_m");
    c.check(q.unknown_low >= 0.0 && q.unknown_low <= 1.0, "unknown_low", "must be in [0, 1]");
    c.check(q.unknown_high >= q.unknown_low && q.unknown_high <= 1.0, "unknown_high", "must be in [unknown_low, 1]");
    c.finish();
  }
  return p;
}

NbvParams NbvParams::load(const std::string& path) {
  YamlReader y = YamlReader::load_file(path);
  NbvParams p = from_yaml(y);
  y.finish();
  return p;
}

YAML::Node NbvParams::to_yaml() const {
  YAML::Node n;
  n["cluster"]["min_logodds"] = cluster.min_logodds;
  n["cluster"]["epsilon_m"] = cluster.epsilon_m;
  n["cluster"]["min_points"] = cluster.min_points;
  n["candidates"]["radius_m"] = candidates.radius_m;
  n["candidates"]["polar_count"] = candidates.polar_count;
  n["candidates"]["polar_min_deg"] = candidates.polar_min_deg;
  n["candidates"]["polar_max_deg"] = candidates.polar_max_deg;
  n["candidates"]["azimuth_count"] = candidates.azimuth_count;
  n["candidates"]["min_height_m"] = candidates.min_height_m;
  n["rays"]["cluster_size_m"] = rays.cluster_size_m;
  n["rays"]["step_m"] = rays.step_m;
  n["rays"]["dense_grid"] = rays.dense_grid;
  n["rays"]["sparse_grid"] = rays.sparse_grid;
  n["rays"]["depth_margin_m"] = rays.depth_margin_m;
  n["gain"]["max_dist_m"] = gain.max_dist_m;
  n["gain"]["proximity"] = to_string(gain.proximity);
  n["gain"]["ae_stop_occupancy"] = gain.ae_stop_occupancy;
  n["gain"]["unknown_low"] = gain.unknown_low;
  n["gain"]["unknown_high"] = gain.unknown_high;
  n["gain"]["uvpc_base_weight"] = gain.uvpc_base_weight;
  n["planner"]["top_k"] = planner.top_k;
  n["views"]["taken_position_m"] = views.taken_position_m;
  n["views"]["taken_angle_deg"] = views.taken_angle_deg;
  n["views"]["done_epsilon_m"] = views.done_epsilon_m;
  n["frontier"]["max_targets"] = frontier.max_targets;
  n["frontier"]["min_view_distance_m"] = frontier.min_view_distance_m;
  n["frontier"]["max_view_distance_m"] = frontier.max_view_distance_m;
  n["frontier"]["roi_inflation_radius_m"] = frontier.roi_inflation_radius_m;
  n["frontier"]["roi_inflation_resolution_m"] = frontier.roi_inflation_resolution_m;
  n["frontier"]["unknown_low"] = frontier.unknown_low;
  n["frontier"]["unknown_high"] = frontier.unknown_high;
  n["frontier"]["unknown_weight"] = frontier.unknown_weight;
  n["frontier"]["roi_weight"] = frontier.roi_weight;
  n["frontier"]["distance_cost_per_m"] = frontier.distance_cost_per_m;
  n["frontier"]["roi_utility_threshold"] = frontier.roi_utility_threshold;
  return n;
}

bool NbvParams::operator==(const NbvParams& o) const {
  const auto& a = *this;
  return a.cluster.min_logodds == o.cluster.min_logodds && a.cluster.epsilon_m == o.cluster.epsilon_m &&
         a.cluster.min_points == o.cluster.min_points && a.candidates.radius_m == o.candidates.radius_m &&
         a.candidates.polar_count == o.candidates.polar_count &&
         a.candidates.polar_min_deg == o.candidates.polar_min_deg &&
         a.candidates.polar_max_deg == o.candidates.polar_max_deg &&
         a.candidates.azimuth_count == o.candidates.azimuth_count &&
         a.candidates.min_height_m == o.candidates.min_height_m && a.rays.cluster_size_m == o.rays.cluster_size_m &&
         a.rays.step_m == o.rays.step_m && a.rays.dense_grid == o.rays.dense_grid &&
         a.rays.sparse_grid == o.rays.sparse_grid && a.rays.depth_margin_m == o.rays.depth_margin_m &&
         a.gain.max_dist_m == o.gain.max_dist_m && a.gain.proximity == o.gain.proximity &&
         a.gain.ae_stop_occupancy == o.gain.ae_stop_occupancy &&
         a.gain.unknown_low == o.gain.unknown_low && a.gain.unknown_high == o.gain.unknown_high &&
         a.gain.uvpc_base_weight == o.gain.uvpc_base_weight && a.planner.top_k == o.planner.top_k &&
         a.views.taken_position_m == o.views.taken_position_m && a.views.taken_angle_deg == o.views.taken_angle_deg &&
         a.views.done_epsilon_m == o.views.done_epsilon_m && a.frontier.max_targets == o.frontier.max_targets &&
         a.frontier.min_view_distance_m == o.frontier.min_view_distance_m &&
         a.frontier.max_view_distance_m == o.frontier.max_view_distance_m &&
         a.frontier.roi_inflation_radius_m == o.frontier.roi_inflation_radius_m &&
         a.frontier.roi_inflation_resolution_m == o.frontier.roi_inflation_resolution_m &&
         a.frontier.unknown_low == o.frontier.unknown_low && a.frontier.unknown_high == o.frontier.unknown_high &&
         a.frontier.unknown_weight == o.frontier.unknown_weight && a.frontier.roi_weight == o.frontier.roi_weight &&
         a.frontier.distance_cost_per_m == o.frontier.distance_cost_per_m &&
         a.frontier.roi_utility_threshold == o.frontier.roi_utility_threshold;
}

}  // namespace canopy::nbv
