#pragma once
// The frontier planner's parameters (the nbv.frontier section of configs/nbv.yaml).

#include "canopy/common/params.h"

namespace canopy::nbv {

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
  /// Views without a collision-free IK goal are dropped when planning (ViewRequest::goal_free);
  /// false: checked only at execution, as Zaenker et al.'s code does (each such view then
  /// costs an attempt that fails before any move).
  bool goal_test_at_planning = true;

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
    a("goal_test_at_planning", goal_test_at_planning,
      "Drop views without a collision-free IK goal when planning (false: at execution, as the authors' code)");
    a.check(max_view_distance_m >= min_view_distance_m, "max_view_distance_m", "must be >= min_view_distance_m");
    a.check(unknown_high >= unknown_low, "unknown_high", "must be in [unknown_low, 1]");
  }
};

}  // namespace canopy::nbv
