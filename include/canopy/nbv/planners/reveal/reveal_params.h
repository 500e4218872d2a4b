#pragma once
// reveal's parameters (the nbv.reveal section of configs/nbv.yaml).

#include <vector>

#include "canopy/common/params.h"

namespace canopy::nbv {

/// canopy's own planner "reveal" (planners/reveal/reveal.h): ours' clusters and reach test, one
/// view at a time on the latest map, scored by the fruit surface it would reveal.
struct RevealParams {
  std::vector<double> radii_m = {0.4};
  int unknown_pass = 3;
  int max_views = 5;

  template <class A>
  void visit(A& a) {
    a("radii_m", radii_m, limits::in(0.05, 2.0),
      "Candidate spheres around each cluster (each like nbv.candidates.sphere) [m]");
    a.check(radii_m.size() <= 16, "radii_m", "holds more than 16 radii (each adds a sphere of candidates per cluster)");
    a("unknown_pass", unknown_pass, limits::in(0, 100000),
      "A sight line to a surface voxel may cross this many unknown voxels (occupied ones always block)");
    a("max_views", max_views, limits::in(1, 1000), "Views per round, best first, tried until one succeeds");
  }
};

}  // namespace canopy::nbv
