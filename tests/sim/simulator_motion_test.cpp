// Motion on the MuJoCo robot: the analytic IK agrees with MuJoCo's kinematics, and planned
// trajectories tracked by the position servos end with the camera within 1 cm and 2 deg
// of the goal without touching the plants or the robot itself.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <random>

#include "canopy/motion/execution.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/mapping/voxel_key.h"
#include "canopy/motion/motion_config.h"
#include "canopy/motion/reachability.h"
#include "canopy/motion/tour.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"
#include "small_worlds.h"

namespace canopy::motion {
namespace {

const RobotModel& model() {
  static const RobotModel m = RobotModel::load(default_robot_config());
  return m;
}

TEST(MotionSim, IkSolutionsPlaceMujocosCameraAtTheGoal) {
  sim::Simulator sim(world::generate_world(test::one_row_spec(1)), default_robot_config());
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-M_PI, M_PI), b(-2.0, 2.0);
  int checked = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const BasePose base{b(rng), b(rng), u(rng)};
    ArmConfig q;
    for (auto& v : q) v = u(rng);
    const Pose goal = model().camera_pose(base, q);
    const IkResult ik = model().camera_ik(base, goal, model().config().home);
    ASSERT_GT(ik.count, 0);
    for (int s = 0; s < ik.count; ++s) {
      sim.set_robot_state(base, ik.q[static_cast<size_t>(s)]);
      const Pose actual = sim.camera_pose();
      double dp, da;
      pose_error(actual, goal, &dp, &da);
      EXPECT_LT(dp, 1e-6);
      EXPECT_LT(da, 1e-6);
      ++checked;
    }
  }
  EXPECT_GT(checked, 400);
}

TEST(MotionSim, PlannedMovesReachTheirViewsWithoutContacts) {
  seed_planner_rng(1);
  const world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/default.yaml"));
  const world::World world = world::generate_world(spec);
  const RobotConfig robot = default_robot_config();
  const MotionConfig cfg = MotionConfig::defaults(robot);
  const std::vector<Vec3> voxels = evaluation::world_occupied_voxels(world, 0.015);
  const auto env = CollisionEnvironment::from_voxels(voxels, 0.015);
  const CollisionChecker checker(model(), cfg.collision, env);
  CollisionParams exact = cfg.collision;
  exact.environment_padding_m = 0.0;  // contacts with the true geometry, no margin
  const CollisionChecker truth(model(), exact, env);
  const ArmPlanner planner(checker, cfg.planner, cfg.trajectory);

  const BasePose base{0.25, 0.0, 0.0};
  ReachParams grid;
  grid.sphere.azimuth_count = 6;
  grid.sphere.polar_count = 3;
  grid.plan = false;
  const ReachReport reach =
      evaluate_reachability(planner, nullptr, base, robot.home, evaluation::world_fruit_centres(world), grid);
  std::vector<Pose> views;
  for (const auto& s : reach.samples)
    if (s.collision_free && views.size() < 4) views.push_back(s.T_world_camera);
  ASSERT_GE(views.size(), 3u);

  sim::Simulator sim(world, robot);
  sim.set_robot_state(base, robot.home);
  // Visit the views in tour order, each move planned from where the arm really is.
  std::vector<ArmConfig> view_q;
  std::vector<Vec3> view_p;
  for (const Pose& v : views) {
    view_q.push_back(model().camera_ik(base, v, robot.home).q[0]);
    view_p.push_back(v.translation());
  }
  const std::vector<int> order = order_views(cfg.tour, robot.home, sim.camera_pose().translation(), view_q, view_p);
  int succeeded = 0;
  for (int i : order) {
    const Pose& goal = views[static_cast<size_t>(i)];
    const PlanResult plan = planner.plan_to_camera_pose(base, sim.arm_positions(), goal);
    ASSERT_TRUE(plan.ok()) << to_string(plan.status) << ": " << plan.message;
    const MoveReport move = execute_arm_move(sim, plan.trajectory, goal, cfg.execution, &truth);
    EXPECT_TRUE(move.success) << move.message;
    EXPECT_EQ(move.contacts(), 0) << (move.contact_pairs.empty() ? "" : *move.contact_pairs.begin());
    EXPECT_GT(move.truth_checks, 10);
    EXPECT_LT(move.duration_s, plan.trajectory.duration() + cfg.execution.settle_time_s + 0.01);
    succeeded += move.success;
    // The base held still.
    EXPECT_NEAR(sim.base_pose().x_m, base.x_m, 0.01);
  }
  EXPECT_EQ(succeeded, static_cast<int>(views.size()));
}

// The truth's voxels against a slow reference: every sample of every triangle (the same
// samples, half a voxel apart) put into an ordered set, nothing skipped or merged before.
TEST(MotionSim, TheTruthVoxelsAreTheVoxelsOfEverySample) {
  const world::World world = world::generate_world(test::one_row_spec(3));
  for (const double res : {0.01, 0.02}) {
    for (const auto& [from, to] : {std::pair{-1e9, 1e9}, std::pair{0.2, 0.9}}) {
      std::set<std::uint64_t> keys;
      for (const auto& plant : world.plants) {
        if (!(plant.base_position.x() >= from && plant.base_position.x() < to)) continue;
        for (const auto& part : plant.parts)
          for (const auto& f : part.mesh.faces) {
            const Vec3 &a = part.mesh.vertices[std::size_t(f[0])], &b = part.mesh.vertices[std::size_t(f[1])],
                       &c = part.mesh.vertices[std::size_t(f[2])];
            const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
            const int n = std::max(1, static_cast<int>(std::ceil(longest / (0.5 * res))));
            for (int i = 0; i <= n; ++i)
              for (int j = 0; j <= n - i; ++j)
                keys.insert(mapping::grid_key(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n), res));
          }
      }
      std::vector<Vec3> want;
      for (const std::uint64_t k : keys) want.push_back(mapping::grid_center(k, res));
      std::sort(want.begin(), want.end(), [](const Vec3& p, const Vec3& q) {
        return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
      });
      const std::vector<Vec3> got = evaluation::world_occupied_voxels(world, res, from, to);
      EXPECT_GT(got.size(), 1000u) << res;
      EXPECT_TRUE(got == want) << "resolution " << res << ", plants from " << from << ": " << got.size() << " voxels, "
                               << want.size() << " in the reference";
    }
  }
}

// A long row's truth per window (issue 49): the voxels of a window's plants are the whole
// row's near them, and the windows either side of a cut cover the whole row's voxels.
TEST(MotionSim, TheTruthVoxelsOfAWindowAreTheWholeRowsNearIt) {
  const world::World world = world::generate_world(test::one_row_spec(6));
  const double res = 0.02;
  const auto key = [](const Vec3& v) { return std::array<double, 3>{v.x(), v.y(), v.z()}; };
  std::set<std::array<double, 3>> whole, left, right;
  for (const Vec3& v : evaluation::world_occupied_voxels(world, res)) whole.insert(key(v));
  for (const Vec3& v : evaluation::world_occupied_voxels(world, res, -10.0, 1.2)) left.insert(key(v));
  for (const Vec3& v : evaluation::world_occupied_voxels(world, res, 1.2, 10.0)) right.insert(key(v));
  EXPECT_GT(left.size(), 0u);
  EXPECT_GT(right.size(), 0u);
  EXPECT_LT(left.size(), whole.size());
  std::set<std::array<double, 3>> both = left;
  both.insert(right.begin(), right.end());
  EXPECT_EQ(both, whole);
  for (const auto& v : left) EXPECT_LT(v[0], 1.2 + 0.5);  // the plants of [.., 1.2) m and their leaves
  EXPECT_EQ(evaluation::world_occupied_voxels(world, res, 20.0, 30.0).size(), 0u);
}

}  // namespace
}  // namespace canopy::motion
