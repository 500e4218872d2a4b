#pragma once
// Parameters of the next-best-view core (paper Methods (iii), Table I; docs/background/nbv_pipeline.md).
// Defaults equal the paper's values; configs/nbv.yaml restates them.

#include <yaml-cpp/yaml.h>

#include <string>

#include "canopy/common/yaml_reader.h"

namespace canopy::nbv {

/// Fruit clustering (DBSCAN over target-class voxels).
struct ClusterParams {
  double min_logodds = 1.0;   ///< A voxel joins when its top class is the target with log-odds above this.
  double epsilon_m = 0.05;    ///< DBSCAN neighbourhood radius (expected fruit radius).
  int min_points = 3;         ///< DBSCAN core-point threshold (neighbours incl. the point).
};

/// Candidate views on a sphere around each cluster centroid.
struct CandidateParams {
  double radius_m = 0.4;         ///< r.
  int polar_count = 5;           ///< N_theta, polar angles from world +z.
  double polar_min_deg = 30.0;   ///< First polar angle.
  double polar_max_deg = 150.0;  ///< Last polar angle (inclusive).
  int azimuth_count = 10;        ///< N_phi, azimuths in [0, 360) without the 360 duplicate.
  double min_height_m = 0.05;    ///< Candidates below this world z are dropped (the floor).
};

/// Ray sets cast from a candidate view.
struct RayParams {
  double cluster_size_m = 0.1;   ///< L: window b = L fx / z around the projected centroid.
  double step_m = 0.015;         ///< delta S: pixel step ds = delta S fx / z (map resolution).
  int dense_grid = 28;           ///< Dense baseline: dense_grid^2 rays over the whole image.
  int sparse_grid = 6;           ///< Sparse baseline: sparse_grid^2 rays over the whole image.
  /// Rays end at planar depth z + depth_margin_m, z = the centroid's depth (paper: L / 2).
  double depth_margin_m = 0.05;
};

/// Gain-function settings.
/// How OSAMCEP tests a voxel's distance to the target (gains.h).
enum class Proximity { kPerVoxel, kPerSegmentEnd };
inline constexpr EnumName<Proximity> kProximityNames[] = {{Proximity::kPerVoxel, "per_voxel"},
                                                          {Proximity::kPerSegmentEnd, "per_segment_end"}};
/// "per_voxel" / "per_segment_end".
std::string to_string(Proximity p);
/// Parses a name; throws InputError naming `where` and the valid names otherwise.
Proximity proximity_from_string(const std::string& s, const std::string& where);

struct GainParams {
  double max_dist_m = 0.1;            ///< OSAMCEP / UVPC: voxels farther from the target do not count.
  Proximity proximity = Proximity::kPerSegmentEnd;  ///< OSAMCEP's distance test (chosen by the ablation).
  double ae_stop_occupancy = 0.9;     ///< AE: the ray stops after the first voxel with p_occ >= this.
  double unknown_low = 0.4;           ///< UVC/UVPC: a known voxel with p in (low, high] is unknown.
  double unknown_high = 0.6;          ///< UVC/UVPC: a voxel with p_occ > high blocks the ray.
  double uvpc_base_weight = 0.5;      ///< UVPC weight = base + (max_dist - d) / max_dist.
};

/// Cluster planner.
struct PlannerParams {
  int top_k = 1;                 ///< Views kept per cluster (prototype: 1).
};

/// Bookkeeping rules of the view planners.
struct ViewRules {
  double taken_position_m = 0.01;  ///< A view within this and taken_angle_deg of a taken one is never taken again.
  double taken_angle_deg = 2.0;
  double done_epsilon_m = 0.05;    ///< A done cluster stays done while a later centroid lies this close.
};

/// Zaenker et al.'s ROI frontier planner as implemented (docs/background/frontier_baseline.md).
struct FrontierParams {
  int max_targets = 100;                  ///< Targets drawn per kind (uniformly, with replacement).
  double min_view_distance_m = 0.3;       ///< Camera origin at U(min, max) from its target.
  double max_view_distance_m = 0.5;
  double roi_inflation_radius_m = 0.3;    ///< Inflated ROI falls linearly from 1 to 0 at this radius.
  double roi_inflation_resolution_m = 0.05;
  double unknown_low = 0.4;               ///< Known voxels with p in (low, high] count as unknown.
  double unknown_high = 0.6;              ///< The utility ray stops at the first voxel with p > high.
  double unknown_weight = 0.5;            ///< An unknown voxel adds unknown_weight + roi_weight * inflated ROI.
  double roi_weight = 0.5;
  double distance_cost_per_m = 0.2;       ///< Utility -= this * distance from the current camera.
  double roi_utility_threshold = 0.2;     ///< ROI views are used when the best ROI utility exceeds this.
};

/// All next-best-view settings (configs/nbv.yaml sections).
struct NbvParams {
  ClusterParams cluster;
  CandidateParams candidates;
  RayParams rays;
  GainParams gain;
  PlannerParams planner;
  ViewRules views;
  FrontierParams frontier;

  /// Reads sections cluster, candidates, rays, gain, planner, views, frontier of one mapping
  /// (InputError on bad values).
  static NbvParams from_yaml(YamlReader& y);
  /// Loads a file and rejects unknown keys.
  static NbvParams load(const std::string& path);
  YAML::Node to_yaml() const;
  bool operator==(const NbvParams& o) const;
};

}  // namespace canopy::nbv
