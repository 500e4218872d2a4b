#pragma once
// The predefined scanning planner's parameters (the nbv.predefined section of configs/nbv.yaml).

#include "canopy/common/params.h"

namespace canopy::nbv {

/// Dense predefined scanning (planners/predefined/predefined.h).
struct PredefinedParams {
  /// A scripted view without a collision-free IK goal at this base (ViewRequest::goal_free) is
  /// refused when the batch is planned and replaced like a failed one, before any move; false:
  /// it is attempted and fails before the arm moves (no_ik, goal_in_collision), then replaced.
  bool goal_test_at_planning = true;

  template <class A>
  void visit(A& a) {
    a("goal_test_at_planning", goal_test_at_planning,
      "Refuse scripted views without a collision-free IK goal when planning, and replace them (false: attempt them)");
  }
};

}  // namespace canopy::nbv
