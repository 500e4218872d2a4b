#include "canopy/motion/tour.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/motion/robot_model.h"

namespace canopy::motion {

namespace {

void check_matrix(const CostMatrix& c) {
  if (c.empty()) throw InputError("tour: empty cost matrix (it needs at least the start)");
  for (const auto& row : c) {
    if (row.size() != c.size()) throw InputError("tour: cost matrix is not square");
    for (double v : row)
      if (!std::isfinite(v)) throw InputError("tour: cost matrix has a non-finite entry");
  }
}

}  // namespace

double tour_cost(const CostMatrix& c, const std::vector<int>& order) {
  double total = 0.0;
  size_t prev = 0;
  for (int v : order) {
    const size_t node = static_cast<size_t>(v) + 1;
    total += c[prev][node];
    prev = node;
  }
  return total;
}

std::vector<int> held_karp_tour(const CostMatrix& c) {
  check_matrix(c);
  const int n = static_cast<int>(c.size()) - 1;
  if (n <= 0) return {};
  CANOPY_CHECK(n <= 20, "Held-Karp with " << n << " views would not fit in memory");
  const size_t full = (size_t{1} << n) - 1;
  const double inf = std::numeric_limits<double>::infinity();
  // dp[mask][j]: cheapest path from the start through the views in mask, ending at view j.
  std::vector<double> dp((full + 1) * static_cast<size_t>(n), inf);
  std::vector<int> parent((full + 1) * static_cast<size_t>(n), -1);
  auto at = [n](size_t mask, int j) { return mask * static_cast<size_t>(n) + static_cast<size_t>(j); };
  for (int j = 0; j < n; ++j) dp[at(size_t{1} << j, j)] = c[0][static_cast<size_t>(j) + 1];
  for (size_t mask = 1; mask <= full; ++mask) {
    for (int j = 0; j < n; ++j) {
      if (!(mask & (size_t{1} << j))) continue;
      const double base = dp[at(mask, j)];
      if (base == inf) continue;
      for (int k = 0; k < n; ++k) {
        if (mask & (size_t{1} << k)) continue;
        const size_t next = mask | (size_t{1} << k);
        const double v = base + c[static_cast<size_t>(j) + 1][static_cast<size_t>(k) + 1];
        if (v < dp[at(next, k)]) {
          dp[at(next, k)] = v;
          parent[at(next, k)] = j;
        }
      }
    }
  }
  int last = 0;
  for (int j = 1; j < n; ++j)
    if (dp[at(full, j)] < dp[at(full, last)]) last = j;
  std::vector<int> order;
  size_t mask = full;
  for (int j = last; j >= 0;) {
    order.push_back(j);
    const int p = parent[at(mask, j)];
    mask &= ~(size_t{1} << j);
    j = p;
  }
  std::reverse(order.begin(), order.end());
  return order;
}

std::vector<int> two_opt_tour(const CostMatrix& c) {
  check_matrix(c);
  const int n = static_cast<int>(c.size()) - 1;
  if (n <= 0) return {};
  // Nodes of the path: p[0] = start (node 0), then views as nodes 1..n.
  std::vector<size_t> p = {0};
  std::vector<char> used(static_cast<size_t>(n) + 1, 0);
  for (int step = 0; step < n; ++step) {
    size_t best = 0;
    double best_c = std::numeric_limits<double>::infinity();
    for (size_t v = 1; v <= static_cast<size_t>(n); ++v)
      if (!used[v] && c[p.back()][v] < best_c) best_c = c[p.back()][v], best = v;
    used[best] = 1;
    p.push_back(best);
  }
  // 2-opt on an open path: reverse p[i..k]; the end after p[n] costs nothing.
  const size_t m = p.size();
  auto edge = [&](size_t a, size_t b) { return b >= m ? 0.0 : c[p[a]][p[b]]; };
  bool improved = true;
  for (int round = 0; improved && round < 1000; ++round) {
    improved = false;
    for (size_t i = 1; i + 1 < m; ++i) {
      for (size_t k = i + 1; k < m; ++k) {
        const double before = edge(i - 1, i) + edge(k, k + 1);
        const double after = c[p[i - 1]][p[k]] + (k + 1 >= m ? 0.0 : c[p[i]][p[k + 1]]);
        if (after < before - 1e-12) {
          std::reverse(p.begin() + static_cast<long>(i), p.begin() + static_cast<long>(k) + 1);
          improved = true;
        }
      }
    }
  }
  std::vector<int> order;
  for (size_t k = 1; k < m; ++k) order.push_back(static_cast<int>(p[k]) - 1);
  return order;
}

std::vector<int> solve_tour(const CostMatrix& cost, int exact_max_views) {
  check_matrix(cost);
  const int n = static_cast<int>(cost.size()) - 1;
  return n <= exact_max_views ? held_karp_tour(cost) : two_opt_tour(cost);
}

CostMatrix joint_cost_matrix(const ArmConfig& start, const std::vector<ArmConfig>& views) {
  std::vector<ArmConfig> nodes = {start};
  nodes.insert(nodes.end(), views.begin(), views.end());
  CostMatrix c(nodes.size(), std::vector<double>(nodes.size(), 0.0));
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t j = 0; j < nodes.size(); ++j) c[i][j] = joint_distance(nodes[i], nodes[j]);
  return c;
}

CostMatrix cartesian_cost_matrix(const Vec3& start, const std::vector<Vec3>& views) {
  std::vector<Vec3> nodes = {start};
  nodes.insert(nodes.end(), views.begin(), views.end());
  CostMatrix c(nodes.size(), std::vector<double>(nodes.size(), 0.0));
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t j = 0; j < nodes.size(); ++j) c[i][j] = (nodes[i] - nodes[j]).norm();
  return c;
}

std::vector<int> order_views(const TourParams& params, const ArmConfig& start_q, const Vec3& start_camera,
                             const std::vector<ArmConfig>& view_q, const std::vector<Vec3>& view_camera) {
  params.validate();
  if (view_q.size() != view_camera.size())
    throw InputError("order_views: " + std::to_string(view_q.size()) + " joint configurations but " +
                     std::to_string(view_camera.size()) + " camera positions");
  if (params.cost == "joint") return solve_tour(joint_cost_matrix(start_q, view_q), params.exact_max_views);
  return solve_tour(cartesian_cost_matrix(start_camera, view_camera), params.exact_max_views);
}

}  // namespace canopy::motion
