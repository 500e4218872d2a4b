#pragma once
// The mobile manipulator as the motion library sees it: fast forward kinematics of every
// link for a base pose and an arm configuration, the camera pose, the analytic camera IK
// in the world, joint limits and the collision bodies. Built once from the robot
// description (URDF) and robot.yaml; immutable and thread-safe afterwards.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "canopy/robot/robot_config.h"
#include "canopy/common/types.h"
#include "canopy/motion/ur_kinematics.h"
#include "canopy/robot/robot_description.h"

namespace canopy::motion {

/// Arm joint limits used for planning: positions from the URDF, rates from robot.yaml.
struct ArmLimits {
  ArmConfig lower{}, upper{};
  ArmConfig max_velocity{}, max_acceleration{};
};

/// One collision shape of the robot, attached to a link.
struct CollisionBody {
  int link = -1;                   ///< Index into description().links().
  robot::Shape shape;              ///< Shape with its pose in the link frame.
  double bounding_radius_m = 0.0;  ///< Sphere around the shape origin enclosing it.
  bool on_arm = false;             ///< Moves with the arm joints (else fixed to the base).
};

/// Camera IK answer: every solution within limits, nearest to the seed first.
struct IkResult {
  std::array<ArmConfig, 8> q;
  int count = 0;
  bool empty() const { return count == 0; }
};

/// Kinematic model of base + arm + camera.
class RobotModel {
 public:
  RobotModel(robot::RobotDescription description, const RobotConfig& config);
  /// Loads the URDF named by `config`; throws InputError on a bad file.
  static RobotModel load(const RobotConfig& config);

  const robot::RobotDescription& description() const { return description_; }
  const RobotConfig& config() const { return config_; }
  const UrKinematics& ur() const { return ur_; }
  const ArmLimits& limits() const { return limits_; }

  /// base_link in the world for a planar base pose.
  static Pose T_world_base(const BasePose& base);
  /// DH frame 0 (arm base) in base_link.
  const Pose& T_base_arm() const { return T_base_arm_; }
  /// Camera optical frame in DH frame 6 (tool0).
  const Pose& T_tool_camera() const { return T_tool_camera_; }

  /// Camera optical frame in the world.
  Pose camera_pose(const BasePose& base, const ArmConfig& q) const;
  /// Camera optical frame in DH frame 0 (the arm base).
  Pose camera_in_arm(const ArmConfig& q) const;

  /// All IK solutions placing the camera at T_world_camera, each joint moved by 2*pi to the
  /// equivalent nearest the seed that is within limits, sorted by joint-space distance to
  /// `seed`. Empty when unreachable or on non-finite input.
  IkResult camera_ik(const BasePose& base, const Pose& T_world_camera, const ArmConfig& seed) const;
  /// Same with the camera pose given in DH frame 0.
  IkResult camera_ik_in_arm(const Pose& T_arm_camera, const ArmConfig& seed) const;

  /// True when every joint is finite and within its position limits.
  bool within_limits(const ArmConfig& q) const;

  /// Poses of all links in the world (indexed like description().links()).
  void link_poses(const BasePose& base, const ArmConfig& q, std::vector<Pose>* poses) const;
  /// Collision shapes of the robot.
  const std::vector<CollisionBody>& bodies() const { return bodies_; }
  /// World poses of the collision shapes (shape frames), indexed like bodies().
  void body_poses(const BasePose& base, const ArmConfig& q, std::vector<Pose>* poses) const;
  /// Whether two links are adjacent for self-collision: one is the nearest ancestor with
  /// collision geometry of the other, or they never move relative to each other.
  bool links_adjacent(int link_a, int link_b) const;

  /// Index of the arm joint driving each link's chain last (-1: base-fixed), for tests.
  const std::vector<int>& link_last_arm_joint() const { return last_arm_joint_; }

 private:
  robot::RobotDescription description_;
  RobotConfig config_;
  UrKinematics ur_;
  ArmLimits limits_;
  Pose T_base_arm_ = Pose::Identity();
  Pose T_tool_camera_ = Pose::Identity();
  Pose T_camera_tool_ = Pose::Identity();
  int base_link_ = -1;
  // Per link: which variable its parent joint reads (-1 fixed, 0..5 arm, 6..8 base x/y/yaw).
  std::vector<int> joint_variable_;
  std::vector<int> parent_link_;
  std::vector<int> last_arm_joint_;
  std::vector<int> collision_ancestor_;  // Nearest ancestor link with collision geometry.
  std::vector<CollisionBody> bodies_;
};

using canopy::joint_distance;  // common/types.h

}  // namespace canopy::motion
