#pragma once
// The global planner's parameters (the nbv.global section of configs/nbv.yaml).

#include "canopy/common/params.h"

namespace canopy::nbv {

/// The global view planner (planners/global/global.h): weighted set cover of the uncertain voxels
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

}  // namespace canopy::nbv
