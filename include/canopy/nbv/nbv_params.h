#pragma once
// Parameters of the next-best-view core (paper Methods (iii), Table I; docs/background/nbv_pipeline.md).
// Defaults equal the paper's values; configs/nbv.yaml restates them.

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/common/view_sphere.h"

namespace canopy::nbv {

/// Fruit clustering (DBSCAN over target-class voxels).
struct ClusterParams {
  double min_logodds = 1.0;
  double epsilon_m = 0.05;
  int min_points = 3;

  template <class A>
  void visit(A& a) {
    a("min_logodds", min_logodds, limits::finite(), "A voxel joins when its top class is the target with log-odds above this");
    a("epsilon_m", epsilon_m, limits::positive(), "DBSCAN neighbourhood radius (expected fruit radius) [m]");
    a("min_points", min_points, limits::in(1, 1000000), "DBSCAN core-point threshold (neighbours incl. the point)");
  }
};

/// Candidate views on a sphere around each cluster centroid (the keys of ViewSphere inline).
struct CandidateParams {
  ViewSphere sphere;
  double min_height_m = 0.05;

  template <class A>
  void visit(A& a) {
    sphere.visit(a);
    a("min_height_m", min_height_m, limits::finite(), "Candidates below this world z are dropped (the floor) [m]");
  }
};

/// Ray sets cast from a candidate view.
struct RayParams {
  double cluster_size_m = 0.1;
  double step_m = 0.015;
  int dense_grid = 28;
  int sparse_grid = 6;
  double depth_margin_m = 0.05;

  template <class A>
  void visit(A& a) {
    a("cluster_size_m", cluster_size_m, limits::positive(), "L: window b = L fx / z around the projected centroid [m]");
    a("step_m", step_m, limits::positive(), "delta S: pixel step ds = delta S fx / z (map resolution) [m]");
    a("dense_grid", dense_grid, limits::in(1, 4096), "Dense baseline: dense_grid^2 rays over the whole image");
    a("sparse_grid", sparse_grid, limits::in(1, 4096), "Sparse baseline: sparse_grid^2 rays over the whole image");
    a("depth_margin_m", depth_margin_m, limits::non_negative(),
      "Rays end at planar depth z + this, z = the centroid's depth (paper: L / 2) [m]");
    // The window grid has (cluster_size / step)^2 rays: keep it a grid, not a flood.
    a.check(cluster_size_m / step_m <= 512.0, "step_m", "is too small for cluster_size_m (more than 512 x 512 rays)");
  }
};

/// How OSAMCEP tests a voxel's distance to the target (gains.h).
enum class Proximity { kPerVoxel, kPerSegmentEnd };
inline constexpr EnumName<Proximity> kProximityNames[] = {{Proximity::kPerVoxel, "per_voxel"},
                                                          {Proximity::kPerSegmentEnd, "per_segment_end"}};
/// "per_voxel" / "per_segment_end".
std::string to_string(Proximity p);
/// Parses a name; throws InputError naming `where` and the valid names otherwise.
Proximity proximity_from_string(const std::string& s, const std::string& where);

/// Gain-function settings.
struct GainParams {
  double max_dist_m = 0.1;
  Proximity proximity = Proximity::kPerSegmentEnd;
  double ae_stop_occupancy = 0.9;
  double unknown_low = 0.4;
  double unknown_high = 0.6;
  double uvpc_base_weight = 0.5;

  template <class A>
  void visit(A& a) {
    a("max_dist_m", max_dist_m, limits::positive(), "OSAMCEP / UVPC: voxels farther from the target do not count [m]");
    a.choice("proximity", proximity, kProximityNames, "OSAMCEP's distance test (chosen by the ablation)");
    a("ae_stop_occupancy", ae_stop_occupancy, limits::above_up_to(0.0, 1.0),
      "AE: the ray stops after the first voxel with p_occ >= this");
    a("unknown_low", unknown_low, limits::in(0.0, 1.0), "UVC/UVPC: a known voxel with p in (low, high] is unknown");
    a("unknown_high", unknown_high, limits::in(0.0, 1.0), "UVC/UVPC: a voxel with p_occ > high blocks the ray");
    a("uvpc_base_weight", uvpc_base_weight, limits::finite(), "UVPC weight = base + (max_dist - d) / max_dist");
    a.check(unknown_high >= unknown_low, "unknown_high", "must be in [unknown_low, 1]");
  }
};

/// Cluster planner.
struct PlannerParams {
  int top_k = 1;

  template <class A>
  void visit(A& a) {
    a("top_k", top_k, limits::in(1, 1000), "Views kept per cluster (prototype: 1)");
  }
};

/// The global view planner (planners/global.h): weighted set cover of the uncertain voxels
/// near the fruit clusters by the stop's reachable candidates, costed by arm motion.
struct GlobalParams {
  double roi_radius_m = 0.08;
  double min_visibility = 0.25;
  double motion_weight_per_rad = 0.1;
  double cover_fraction = 0.9;

  template <class A>
  void visit(A& a) {
    a("roi_radius_m", roi_radius_m, limits::positive(),
      "A voxel counts when its centre lies within this of a fruit cluster's centroid [m]");
    a("min_visibility", min_visibility, limits::above_up_to(0.0, 1.0),
      "A view observes a voxel while prod (1 - p_occ) of the occupied voxels before it on a ray is at least this");
    a("motion_weight_per_rad", motion_weight_per_rad, limits::at_least(0.0),
      "Cost of a view: 1 + this x its joint-space distance from the arm now [1/rad]");
    a("cover_fraction", cover_fraction, limits::above_up_to(0.0, 1.0),
      "A batch ends once its views observe this share of what all candidates observe");
  }
};

/// Bookkeeping rules of the view planners.
struct ViewRules {
  double taken_position_m = 0.01;
  double taken_angle_deg = 2.0;
  double done_epsilon_m = 0.05;

  template <class A>
  void visit(A& a) {
    a("taken_position_m", taken_position_m, limits::positive(),
      "A view within this and taken_angle_deg of a taken one is never taken again [m]");
    a("taken_angle_deg", taken_angle_deg, limits::positive(), "... and within this angle [deg]");
    a("done_epsilon_m", done_epsilon_m, limits::positive(),
      "A done cluster stays done while a later centroid lies this close [m]");
  }
};

/// Zaenker et al.'s ROI frontier planner as implemented (docs/background/frontier_baseline.md).
struct FrontierParams {
  int max_targets = 100;
  double min_view_distance_m = 0.3;
  double max_view_distance_m = 0.5;
  double roi_inflation_radius_m = 0.3;
  double roi_inflation_resolution_m = 0.05;
  double unknown_low = 0.4;
  double unknown_high = 0.6;
  double unknown_weight = 0.5;
  double roi_weight = 0.5;
  double distance_cost_per_m = 0.2;
  double roi_utility_threshold = 0.2;

  template <class A>
  void visit(A& a) {
    a("max_targets", max_targets, limits::in(1, 100000), "Targets drawn per kind (uniformly, with replacement)");
    a("min_view_distance_m", min_view_distance_m, limits::positive(), "Camera origin at U(min, max) from its target [m]");
    a("max_view_distance_m", max_view_distance_m, limits::positive(), "... [m]");
    a("roi_inflation_radius_m", roi_inflation_radius_m, limits::positive(),
      "Inflated ROI falls linearly from 1 to 0 at this radius [m]");
    a("roi_inflation_resolution_m", roi_inflation_resolution_m, limits::positive(), "Cell of the inflated ROI [m]");
    a("unknown_low", unknown_low, limits::in(0.0, 1.0), "Known voxels with p in (low, high] count as unknown");
    a("unknown_high", unknown_high, limits::in(0.0, 1.0), "The utility ray stops at the first voxel with p > high");
    a("unknown_weight", unknown_weight, limits::finite(), "An unknown voxel adds unknown_weight + roi_weight * inflated ROI");
    a("roi_weight", roi_weight, limits::finite(), "See unknown_weight");
    a("distance_cost_per_m", distance_cost_per_m, limits::finite(), "Utility -= this * distance from the current camera");
    a("roi_utility_threshold", roi_utility_threshold, limits::finite(),
      "ROI views are used when the best ROI utility exceeds this");
    a.check(max_view_distance_m >= min_view_distance_m, "max_view_distance_m", "must be >= min_view_distance_m");
    a.check(unknown_high >= unknown_low, "unknown_high", "must be in [unknown_low, 1]");
  }
};

/// canopy's own planner "reveal" (planners/reveal.h): ours' clusters and reach test, one view
/// at a time on the latest map, scored by the fruit surface it would reveal.
struct RevealParams {
  std::vector<double> radii_m = {0.4};
  int unknown_pass = 3;
  int max_views = 5;

  template <class A>
  void visit(A& a);
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
  GlobalParams global;
  RevealParams reveal;

  template <class A>
  void visit(A& a) {
    a.section("cluster", cluster, "Fruit clustering (DBSCAN)");
    a.section("candidates", candidates, "Candidate views on a sphere around each cluster");
    a.section("rays", rays, "Ray sets cast from a candidate view");
    a.section("gain", gain, "Information gains");
    a.section("planner", planner, "The cluster planner");
    a.section("views", views, "Taken views and done clusters");
    a.section("frontier", frontier, "The frontier baseline");
    a.section("global", global, "The global view planner (set cover of the stop's candidates)");
    a.section("reveal", reveal, "canopy's own planner (method reveal)");
  }
  bool operator==(const NbvParams& o) const { return same_params(*this, o); }
};

template <class A>
void RevealParams::visit(A& a) {
  a("radii_m", radii_m, limits::in(0.05, 2.0), "Candidate spheres around each cluster (each like nbv.candidates.sphere) [m]");
  a("unknown_pass", unknown_pass, limits::in(0, 100000),
    "A sight line to a surface voxel may cross this many unknown voxels (occupied ones always block)");
  a("max_views", max_views, limits::in(1, 1000), "Views per round, best first, tried until one succeeds");
}

}  // namespace canopy::nbv
