#include "canopy/robot/robot_description.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"

namespace canopy::robot {
namespace {

// Standard DH product for the UR3 (docs/background/robot_and_camera.md), the reference for the URDF chain.
Pose dh_fk(const std::array<double, 6>& q) {
  const double d[6] = {0.1519, 0, 0, 0.11235, 0.08535, 0.0819};
  const double a[6] = {0, -0.24365, -0.21325, 0, 0, 0};
  const double alpha[6] = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};
  Pose T = Pose::Identity();
  for (int i = 0; i < 6; ++i) {
    Pose A = Pose::Identity();
    A.rotate(Eigen::AngleAxisd(q[i], Vec3::UnitZ()));
    A.translate(Vec3(a[i], 0, d[i]));
    A.rotate(Eigen::AngleAxisd(alpha[i], Vec3::UnitX()));
    T = T * A;
  }
  return T;
}

TEST(RobotDescription, LoadsTheRobotAndKeepsTopologicalOrder) {
  const RobotConfig cfg = default_robot_config();
  const RobotDescription d = RobotDescription::load_urdf(cfg.urdf_path);
  EXPECT_EQ(d.links().front().name, "world");
  for (size_t i = 1; i < d.links().size(); ++i) EXPECT_LT(d.parent_link(static_cast<int>(i)), static_cast<int>(i));
  for (const auto& j : cfg.arm_joints) EXPECT_TRUE(d.joint(j).movable());
  // Capsule convention: collision cylinders named *_capsule are capsules.
  int capsules = 0;
  for (const auto& l : d.links())
    for (const auto& s : l.collisions) capsules += s.type == ShapeType::kCapsule;
  EXPECT_GE(capsules, 6);
}

TEST(RobotDescription, BaseFootprintHalfWidthIsTheChassisBox) {
  const RobotDescription d = RobotDescription::load_urdf(default_robot_config().urdf_path);
  // Husky A200 chassis collision box: 0.99 x 0.67 m.
  EXPECT_NEAR(d.collision_half_width_m("base_link"), 0.335, 1e-12);
  EXPECT_EQ(d.collision_half_width_m("world"), 0.0);
}

TEST(RobotDescription, ArmChainEqualsStandardDh) {
  const RobotConfig cfg = default_robot_config();
  const RobotDescription d = RobotDescription::load_urdf(cfg.urdf_path);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  for (int trial = 0; trial < 200; ++trial) {
    std::array<double, 6> q;
    JointPositions jp;
    for (int i = 0; i < 6; ++i) {
      q[i] = u(rng);
      jp[cfg.arm_joints[i]] = q[i];
    }
    const Pose T_urdf = d.relative_pose(cfg.arm_base_frame, cfg.tool_frame, jp);
    const Pose T_dh = dh_fk(q);
    EXPECT_LT((T_urdf.translation() - T_dh.translation()).norm(), 1e-12);
    EXPECT_LT((T_urdf.linear() - T_dh.linear()).norm(), 1e-12);
  }
}

TEST(RobotDescription, LinkPosesAgreeWithChainProduct) {
  const RobotDescription d = RobotDescription::load_urdf(default_robot_config().urdf_path);
  JointPositions q{{"base_x", 1.2}, {"base_y", -0.3}, {"base_yaw", 0.7}, {"elbow_joint", 0.4}};
  const auto all = d.link_poses(q);
  for (size_t i = 0; i < d.links().size(); ++i) {
    const Pose T = d.link_pose(d.links()[i].name, q);
    EXPECT_LT((all[i].matrix() - T.matrix()).norm(), 1e-12) << d.links()[i].name;
  }
  // The planar base joints move base_link as x, y, yaw.
  const Pose T_base = d.link_pose("base_link", q);
  EXPECT_NEAR(T_base.translation().x(), 1.2, 1e-12);
  EXPECT_NEAR(T_base.translation().y(), -0.3, 1e-12);
  EXPECT_NEAR(std::atan2(T_base.linear()(1, 0), T_base.linear()(0, 0)), 0.7, 1e-12);
}

TEST(RobotDescription, BadFilesGiveInputErrors) {
  EXPECT_THROW(RobotDescription::load_urdf("/nonexistent/robot.urdf"), InputError);
  const RobotDescription d = RobotDescription::load_urdf(default_robot_config().urdf_path);
  EXPECT_THROW(d.link_index("no_such_link"), InputError);
  EXPECT_THROW(d.relative_pose("tool0", "base_link", {}), InputError);
}

}  // namespace
}  // namespace canopy::robot
