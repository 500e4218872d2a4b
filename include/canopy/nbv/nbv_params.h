#pragma once
// Parameters of the next-best-view core (paper Methods (iii), Table I; docs/background/nbv_pipeline.md)
// and the nbv section of the settings bundle. Each built-in planner's own parameters live in its
// room (planners/<name>/<name>_params.h) and join the section nbv.<name> through its registry
// entry (ViewPlannerEntry::params): this file names no planner. Defaults equal the paper's
// values; configs/nbv.yaml is what YamlDoc writes of them (a test holds it so).

#include <yaml-cpp/yaml.h>

#include <string>
#include <typeinfo>
#include <vector>

#include "canopy/common/any_params.h"
#include "canopy/common/error.h"
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

/// A planner's own parameter section, nbv.<key>, carried by its registry entry
/// (ViewPlannerEntry::params).
struct PlannerSection {
  std::string key;         ///< Its key under nbv: the planner's registry name.
  std::string help;        ///< One line for the reference of every setting.
  AnyParams params;        ///< Its parameter struct, holding the defaults.
  std::string former_key;  ///< A key it had before, still read with a warning ("": none).
};

/// A registry entry's section: the struct P with P's defaults (the key is the entry's name).
template <class P>
PlannerSection planner_section(const std::string& help, const std::string& former_key = "") {
  return {"", help, AnyParams(P{}), former_key};
}

/// Every built-in planner's section, from builtin_view_planners() (planners/planners.h), in
/// the registry's order, with their defaults.
const std::vector<PlannerSection>& builtin_planner_sections();

/// All next-best-view settings (configs/nbv.yaml sections).
struct NbvParams {
  ClusterParams cluster;
  CandidateParams candidates;
  RayParams rays;
  GainParams gain;
  ViewRules views;
  /// The built-in planners' own sections (nbv.ours, nbv.frontier, ...), in the registry's order.
  std::vector<PlannerSection> planners = builtin_planner_sections();

  /// A planner's own parameters, by their type (ours: OursParams, frontier: FrontierParams, ...).
  template <class P>
  P& planner() {
    for (PlannerSection& s : planners)
      if (P* p = s.params.get<P>()) return *p;
    throw InternalError(std::string("nbv settings: no planner section holds ") + typeid(P).name());
  }
  template <class P>
  const P& planner() const {
    return const_cast<NbvParams*>(this)->planner<P>();
  }

  template <class A>
  void visit(A& a) {
    a.section("cluster", cluster, "Fruit clustering (DBSCAN)");
    a.section("candidates", candidates, "Candidate views on a sphere around each cluster");
    a.section("rays", rays, "Ray sets cast from a candidate view");
    a.section("gain", gain, "Information gains");
    a.section("views", views, "Taken views and done clusters");
    for (PlannerSection& s : planners) {
      if (!s.former_key.empty()) a.renamed(s.former_key.c_str(), s.key.c_str());
      a.section(s.key.c_str(), s.params, s.help.c_str());
    }
  }
  bool operator==(const NbvParams& o) const { return same_params(*this, o); }
};

}  // namespace canopy::nbv
