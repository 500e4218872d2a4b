#pragma once
// learned's parameters (the nbv.learned section of configs/nbv.yaml).

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/mapping/shape_fit.h"

namespace canopy::nbv {

/// The planner on the learned view scorer "learned" (planners/learned/learned.h).
struct LearnedParams {
  std::string model = "models/nbv/view_ranker.json";
  mapping::ShapeFitParams fit;
  double fruit_min_logodds = 0.0;
  std::vector<double> radii_m = {0.4};
  double spacing_m = 0.01;
  double covered_m = 0.015;
  double unknown_transmit = 0.97;
  int max_views = 5;

  template <class A>
  void visit(A& a) {
    a("model", model,
      "The view scorer: an XGBoost model over the view features (tools/train_view_ranker.py; relative paths "
      "from the data folder); missing, corrupt or trained on other features: refused");
    a.section("fit", fit, "The fruit shape fit of the features (as nbv.shape.fit)");
    a("fruit_min_logodds", fruit_min_logodds, limits::finite(),
      "A voxel is one of a fruit's (clustered, fitted, seen) when its top class is the fruit with log-odds above "
      "this: 0 takes a voxel hit once as fruit, nbv.cluster.min_logodds (1, the other planners') twice; chosen in "
      "closed loop on tuning worlds (docs/learned.md)");
    a("radii_m", radii_m, limits::in(0.05, 2.0), "Candidate spheres around each fitted fruit centre [m]");
    a.check(radii_m.size() <= 16, "radii_m", "holds more than 16 radii (each adds a sphere of candidates per fruit)");
    a("spacing_m", spacing_m, limits::in(0.001, 0.1), "Spacing of the predicted surface points of the features [m]");
    a("covered_m", covered_m, limits::in(0.0, 0.1),
      "A predicted point is seen when a confirmed fruit voxel centre lies this close [m]");
    a("unknown_transmit", unknown_transmit, limits::in(0.0, 1.0),
      "Each unknown voxel on a sight line passes it with this factor (the shape features)");
    a("max_views", max_views, limits::in(1, 1000), "Views per round, best first, tried until one succeeds");
  }
};

}  // namespace canopy::nbv
