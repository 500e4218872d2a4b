#pragma once
// shape's parameters (the nbv.shape section of configs/nbv.yaml).

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/mapping/shape_fit.h"

namespace canopy::nbv {

/// The shape-completion planner "shape" (planners/shape/shape.h): every fruit cluster fitted
/// with a spheroid, views scored by the predicted fruit surface they would newly see.
struct ShapeParams {
  mapping::ShapeFitParams fit;
  std::vector<double> radii_m = {0.4};
  double spacing_m = 0.01;
  double covered_m = 0.015;
  double unknown_transmit = 0.97;
  double uvc_weight = 0.0;
  std::string other_class = "refute";
  int max_views = 5;
  std::string fallback = "none";

  template <class A>
  void visit(A& a) {
    a.section("fit", fit, "The fruit shape fit (a spheroid with the world's fruit-size prior)");
    a("radii_m", radii_m, limits::in(0.05, 2.0),
      "Candidate spheres around each fitted fruit centre (each like nbv.candidates.sphere) [m]");
    a.check(radii_m.size() <= 16, "radii_m", "holds more than 16 radii (each adds a sphere of candidates per cluster)");
    a("spacing_m", spacing_m, limits::in(0.001, 0.1), "Spacing of the predicted surface points [m]");
    a("covered_m", covered_m, limits::in(0.0, 0.1),
      "A predicted point is seen when a confirmed fruit voxel centre lies this close (delta S) [m]");
    a("unknown_transmit", unknown_transmit, limits::in(0.0, 1.0),
      "Each unknown voxel on a sight line passes it with this factor (occupied ones block)");
    a("uvc_weight", uvc_weight, limits::in(0.0, 1e6),
      "Score = predicted points seen + this x unknown voxels counted (uvc over ours' rays)");
    a.one_of("other_class", other_class, {"refute", "fruit_probability"},
             "A predicted point in a voxel the map knows as another class's surface: refuted, or counted x "
             "the voxel's fruit probability among its occupied classes");
    a("max_views", max_views, limits::in(1, 1000), "Views per round, best first, tried until one succeeds");
    a.one_of("fallback", fallback, {"none", "frontier"},
             "When no view sees predicted fruit surface: the stop ends (none), or that round is frontier's "
             "(its ROI and exploration views); shape plans again first the next round");
  }
};

}  // namespace canopy::nbv
