#include "canopy/motion/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/motion/robot_model.h"

namespace canopy::motion {
namespace {

const ArmConfig kV = {3.14, 3.14, 3.14, 6.28, 6.28, 6.28};
const ArmConfig kA = {3, 3, 3, 6, 6, 6};

TEST(Trajectory, WithinLimitsThroughWaypoints) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<ArmConfig> path(2 + trial % 4);
    for (auto& q : path)
      for (auto& v : q) v = u(rng);
    if (trial % 5 == 0) path[1][3] = path[0][3] + 1e-3;  // A short move: triangular profile.
    const ArmTrajectory t = ArmTrajectory::time_parameterize(path, kV, kA);
    ASSERT_EQ(t.waypoints().size(), path.size());
    EXPECT_GT(t.duration(), 0.0);
    for (size_t k = 0; k < path.size(); ++k) {
      const ArmReference r = t.sample(t.times()[k]);
      for (int i = 0; i < kArmDof; ++i) {
        EXPECT_NEAR(r.q[i], path[k][i], 1e-9);
        EXPECT_NEAR(r.qd[i], 0.0, 1e-6);  // Stops at each waypoint.
      }
    }
    EXPECT_TRUE(t.sample(t.duration() + 1.0).finished);
    EXPECT_FALSE(t.sample(0.0).finished);
    // Limits, checked on the analytic derivatives and by finite differences.
    const double dt = 1e-4;
    ArmReference prev = t.sample(0.0);
    for (double time = dt; time < t.duration(); time += dt) {
      const ArmReference r = t.sample(time);
      for (int i = 0; i < kArmDof; ++i) {
        EXPECT_LE(std::abs(r.qd[i]), kV[i] * (1 + 1e-9));
        EXPECT_LE(std::abs(r.qdd[i]), kA[i] * (1 + 1e-9));
        EXPECT_LE(std::abs(r.q[i] - prev.q[i]) / dt, kV[i] * (1 + 1e-6));
        EXPECT_LE(std::abs(r.qd[i] - prev.qd[i]) / dt, kA[i] * (1 + 1e-6));
      }
      prev = r;
    }
  }
}

TEST(Trajectory, OneJointAtItsLimitIsTimeOptimal) {
  // Joint 0 moves 3.14 rad at 3.14 rad/s, 3 rad/s^2: t_acc = 1.047 s, cruise 0.0 + ...
  std::vector<ArmConfig> path = {ArmConfig{}, ArmConfig{}};
  path[1][0] = 4.0;
  const ArmTrajectory t = ArmTrajectory::time_parameterize(path, kV, kA);
  const double t_acc = kV[0] / kA[0];
  const double expected = 2 * t_acc + (4.0 - kV[0] * t_acc) / kV[0];
  EXPECT_NEAR(t.duration(), expected, 1e-9);
  EXPECT_NEAR(t.sample(t.duration() / 2).qd[0], kV[0], 1e-9);
}

TEST(Trajectory, DegenerateAndBadInput) {
  const ArmConfig q = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  const ArmTrajectory single = ArmTrajectory::time_parameterize({q}, kV, kA);
  EXPECT_EQ(single.duration(), 0.0);
  EXPECT_TRUE(single.sample(0.0).finished);
  EXPECT_EQ(single.sample(1.0).q, q);
  const ArmTrajectory repeated = ArmTrajectory::time_parameterize({q, q, q}, kV, kA);
  EXPECT_EQ(repeated.waypoints().size(), 1u);
  EXPECT_THROW(ArmTrajectory::time_parameterize({}, kV, kA), InputError);
  ArmConfig bad = q;
  bad[2] = std::nan("");
  EXPECT_THROW(ArmTrajectory::time_parameterize({q, bad}, kV, kA), InputError);
  ArmConfig zero_v = kV;
  zero_v[1] = 0.0;
  EXPECT_THROW(ArmTrajectory::time_parameterize({q, q}, zero_v, kA), InputError);
  ArmConfig q2 = q;
  q2[0] += 1.0;
  const ArmTrajectory t = ArmTrajectory::time_parameterize({q, q2}, kV, kA);
  EXPECT_EQ(t.sample(std::nan("")).q, q);  // NaN time holds the start
  EXPECT_EQ(t.sample(-5.0).q, q);
}

TEST(Trajectory, ScaledLimitsAndParams) {
  ArmLimits lim;
  lim.max_velocity = kV;
  lim.max_acceleration = kA;
  std::vector<ArmConfig> path = {ArmConfig{}, ArmConfig{}};
  path[1][1] = 2.0;
  TrajectoryParams half;
  half.velocity_scale = 0.5;
  half.acceleration_scale = 0.25;
  const double full = ArmTrajectory::time_parameterize(path, lim, TrajectoryParams{}).duration();
  const double slow = ArmTrajectory::time_parameterize(path, lim, half).duration();
  EXPECT_NEAR(slow, 2.0 * full, 1e-9);  // v/2 and a/4 exactly double the time.
  YamlReader y = YamlReader::load_string("velocity_scale: 0.3\n", "t");
  EXPECT_EQ(params_from_yaml<TrajectoryParams>(y).velocity_scale, 0.3);
  YamlReader bad = YamlReader::load_string("acceleration_scale: 1.5\n", "t");
  EXPECT_THROW(params_from_yaml<TrajectoryParams>(bad), InputError);
  EXPECT_THROW(TrajectoryTracker(ArmTrajectory{}, -1.0), InputError);
}

TEST(Trajectory, PoseWithin) {
  Pose a = Pose::Identity();
  Pose b = a;
  b.translation().x() = 0.009;
  b.rotate(Eigen::AngleAxisd(1.9 * M_PI / 180, Vec3::UnitY()));
  EXPECT_TRUE(pose_within(a, b, 0.01, 2 * M_PI / 180));
  b.translation().x() = 0.011;
  EXPECT_FALSE(pose_within(a, b, 0.01, 2 * M_PI / 180));
}

}  // namespace
}  // namespace canopy::motion
