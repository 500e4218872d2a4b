// robot.yaml against the struct defaults (robot/robot_config.h).
#include <gtest/gtest.h>

#include "canopy/robot/robot_config.h"

namespace canopy {
namespace {

TEST(RobotConfig, DefaultsEqualTheShippedYaml) {
  const RobotConfig file = default_robot_config();
  const RobotConfig defaults;
  EXPECT_EQ(file.home, defaults.home);
  EXPECT_EQ(file.arm_kp, defaults.arm_kp);
  EXPECT_EQ(file.arm_joints, defaults.arm_joints);
  EXPECT_EQ(file.base_kv, defaults.base_kv);
  EXPECT_EQ(file.arm_max_velocity, defaults.arm_max_velocity);
  EXPECT_EQ(file.aisle_clearance_m, defaults.aisle_clearance_m);
}

}  // namespace
}  // namespace canopy
