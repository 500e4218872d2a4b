#include "canopy/motion/tour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {
namespace {

// Slow reference: every permutation.
double brute_force_cost(const CostMatrix& c) {
  std::vector<int> order(c.size() - 1);
  std::iota(order.begin(), order.end(), 0);
  double best = 1e300;
  do best = std::min(best, tour_cost(c, order));
  while (std::next_permutation(order.begin(), order.end()));
  return best;
}

bool is_permutation_of_views(const std::vector<int>& order, size_t n) {
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 0; i < sorted.size(); ++i)
    if (sorted[i] != static_cast<int>(i)) return false;
  return sorted.size() == n;
}

TEST(Tour, HeldKarpEqualsBruteForceUpToEightViews) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n <= 8; ++n) {
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<ArmConfig> views(static_cast<size_t>(n));
      for (auto& q : views)
        for (auto& v : q) v = u(rng);
      ArmConfig start{};
      const CostMatrix c = joint_cost_matrix(start, views);
      const std::vector<int> order = held_karp_tour(c);
      ASSERT_TRUE(is_permutation_of_views(order, views.size()));
      if (n > 0) {
        EXPECT_NEAR(tour_cost(c, order), brute_force_cost(c), 1e-9) << n << " views";
      }
      // Asymmetric costs too (Held-Karp does not need symmetry).
      CostMatrix a = c;
      for (auto& row : a)
        for (auto& v : row) v += 0.3 * std::abs(u(rng));
      const std::vector<int> ao = held_karp_tour(a);
      if (n > 0) {
        EXPECT_NEAR(tour_cost(a, ao), brute_force_cost(a), 1e-9);
      }
    }
  }
}

TEST(Tour, TwoOptIsCloseToOptimalAndValid) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double ratio_sum = 0;
  const int trials = 20;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<Vec3> views(8);
    for (auto& v : views) v = Vec3(u(rng), u(rng), u(rng));
    const CostMatrix c = cartesian_cost_matrix(Vec3::Zero(), views);
    const std::vector<int> order = two_opt_tour(c);
    ASSERT_TRUE(is_permutation_of_views(order, views.size()));
    const double opt = brute_force_cost(c);
    EXPECT_LE(tour_cost(c, order), 1.3 * opt);
    ratio_sum += tour_cost(c, order) / opt;
  }
  EXPECT_LT(ratio_sum / trials, 1.05);
  // Collinear points: 2-opt finds the obvious order.
  std::vector<Vec3> line;
  for (int k : {3, 1, 4, 0, 2}) line.push_back(Vec3(1.0 + k, 0, 0));
  const std::vector<int> o = two_opt_tour(cartesian_cost_matrix(Vec3::Zero(), line));
  EXPECT_EQ(o, (std::vector<int>{3, 1, 4, 0, 2}));
}

TEST(Tour, SolveSwitchesAtTheLimitAndHandlesLargeInputs) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  std::vector<Vec3> views(60);
  for (auto& v : views) v = Vec3(u(rng), u(rng), 0.0);
  const CostMatrix c = cartesian_cost_matrix(Vec3::Zero(), views);
  const std::vector<int> order = solve_tour(c, 12);
  ASSERT_TRUE(is_permutation_of_views(order, views.size()));
  // 12 views: exact.
  std::vector<Vec3> twelve(views.begin(), views.begin() + 12);
  const CostMatrix c12 = cartesian_cost_matrix(Vec3::Zero(), twelve);
  EXPECT_NEAR(tour_cost(c12, solve_tour(c12, 12)), tour_cost(c12, held_karp_tour(c12)), 1e-12);
  EXPECT_LE(tour_cost(c12, held_karp_tour(c12)), tour_cost(c12, two_opt_tour(c12)) + 1e-12);
}

TEST(Tour, OrderViewsAndBadInput) {
  const std::vector<ArmConfig> q = {{3, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 0, 0}, {2, 0, 0, 0, 0, 0}};
  const std::vector<Vec3> p = {Vec3(0, 0, 1), Vec3(0, 0, 3), Vec3(0, 0, 2)};
  TourParams joint;
  EXPECT_EQ(order_views(joint, ArmConfig{}, Vec3::Zero(), q, p), (std::vector<int>{1, 2, 0}));
  TourParams cart;
  cart.cost = "cartesian";
  EXPECT_EQ(order_views(cart, ArmConfig{}, Vec3::Zero(), q, p), (std::vector<int>{0, 2, 1}));
  EXPECT_TRUE(solve_tour(CostMatrix{{0.0}}).empty());
  EXPECT_THROW(solve_tour(CostMatrix{}), InputError);
  EXPECT_THROW(solve_tour(CostMatrix{{0, 1}, {1}}), InputError);
  EXPECT_THROW(solve_tour(CostMatrix{{0, std::nan("")}, {1, 0}}), InputError);
  YamlReader y = YamlReader::load_string("cost: euclid\n", "t");
  EXPECT_THROW(params_from_yaml<TourParams>(y), InputError);
}

}  // namespace
}  // namespace canopy::motion
