#pragma once
// Ordering the chosen views (the paper's Methods iv): an open travelling-salesman tour that
// starts at the current configuration and visits every view once. Exact (Held-Karp) up to
// a size limit (12 views by default), nearest neighbour + 2-opt beyond. Cost in joint space
// by default (distance between IK configurations), Cartesian camera distance as an option.

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/types.h"

namespace canopy {
class YamlReader;
}

namespace canopy::motion {

/// A square cost matrix; node 0 is the start, nodes 1..n the views.
using CostMatrix = std::vector<std::vector<double>>;

/// Tour settings (configs/motion.yaml, section "tour").
struct TourParams {
  int exact_max_views = 12;   ///< Held-Karp up to this many views, 2-opt beyond.
  std::string cost = "joint";  ///< "joint" (Euclidean joint distance) or "cartesian".

  template <class A>
  void visit(A& a) {
    a("exact_max_views", exact_max_views, limits::in(0, 16), "Held-Karp up to this many views, 2-opt beyond");
    a.one_of("cost", cost, {"joint", "cartesian"}, "Tour cost: joint-space or Cartesian camera distance");
  }
  void validate() const { validate_params(*this, "tour"); }
};

/// Total cost of visiting `order` (view indices 0..n-1, i.e. nodes 1..n) from node 0.
double tour_cost(const CostMatrix& cost, const std::vector<int>& order);
/// Exact open tour from node 0 by dynamic programming, O(2^n n^2); n <= 20.
std::vector<int> held_karp_tour(const CostMatrix& cost);
/// Nearest-neighbour tour improved by 2-opt moves until none helps (symmetric costs).
std::vector<int> two_opt_tour(const CostMatrix& cost);
/// Held-Karp when n <= exact_max_views, else 2-opt. Returns view indices in visiting order.
/// Throws InputError on a non-square matrix or non-finite costs.
std::vector<int> solve_tour(const CostMatrix& cost, int exact_max_views = 12);

/// Cost matrices from the start and the views.
CostMatrix joint_cost_matrix(const ArmConfig& start, const std::vector<ArmConfig>& views);
CostMatrix cartesian_cost_matrix(const Vec3& start, const std::vector<Vec3>& views);

/// Orders views per `params`: joint configurations are used for "joint", camera positions
/// for "cartesian" (both lists describe the same views, in the same order).
std::vector<int> order_views(const TourParams& params, const ArmConfig& start_q, const Vec3& start_camera,
                             const std::vector<ArmConfig>& view_q, const std::vector<Vec3>& view_camera);

}  // namespace canopy::motion
