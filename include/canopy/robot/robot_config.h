#pragma once
// How the robot described in the URDF is driven and limited (models/robot/robot.yaml).
// Kinematics and geometry come only from the URDF; this holds names, gains and limits.

#include <array>
#include <string>
#include <vector>

#include "canopy/common/data_dir.h"
#include "canopy/common/types.h"

namespace canopy {

/// Robot metadata loaded from robot.yaml (paths resolved to absolute).
struct RobotConfig {
  std::string urdf_path;                       ///< Absolute path of the URDF.
  std::string camera_frame = "camera_optical_frame";
  std::string tool_frame = "tool0";
  std::string arm_base_frame = "arm_base_link";
  std::vector<std::string> base_joints = {"base_x", "base_y", "base_yaw"};
  std::vector<std::string> arm_joints = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                         "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"};
  ArmConfig home = {-2.1738, -0.5441, 2.3290, 1.3567, -0.9678, 0.0};
  ArmConfig arm_max_velocity = {3.1416, 3.1416, 3.1416, 6.2832, 6.2832, 6.2832};
  ArmConfig arm_max_acceleration = {3.0, 3.0, 3.0, 6.0, 6.0, 6.0};
  double base_max_speed_m_s = 1.0;
  double base_max_yaw_rate_rad_s = 2.0;
  double base_max_accel_m_s2 = 1.0;
  double base_max_yaw_accel_rad_s2 = 2.0;
  ArmConfig arm_kp = {2000, 2000, 1000, 300, 300, 300};
  ArmConfig arm_armature = {0.1, 0.1, 0.05, 0.02, 0.02, 0.02};
  std::array<double, 3> base_kv = {5000, 5000, 2000};
  bool gravity_compensation = true;
  /// Free space required on each side of the base between the aisle's centre line and the
  /// nearest reach of a plant (world validation: an aisle narrower than the base plus twice
  /// this is rejected).
  double aisle_clearance_m = 0.05;

  /// Loads robot.yaml; throws InputError naming the file and key on bad input.
  static RobotConfig load(const std::string& yaml_path);
};

/// The default robot description: models/robot/robot.yaml.
RobotConfig default_robot_config();

}  // namespace canopy
