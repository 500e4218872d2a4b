#pragma once
// ours' own parameters (the nbv.ours section of configs/nbv.yaml; nbv.planner before, still
// read with a warning); ours also reads the shared sections cluster, candidates, rays, gain and
// views.

#include "canopy/common/params.h"

namespace canopy::nbv {

/// The cluster planner's own parameters.
struct OursParams {
  int top_k = 1;

  template <class A>
  void visit(A& a) {
    a("top_k", top_k, limits::in(1, 1000), "Views kept per cluster (prototype: 1)");
  }
};

}  // namespace canopy::nbv
