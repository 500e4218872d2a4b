#pragma once
// Eigen aliases used across canopy. Poses are rigid transforms named T_<to>_<from>:
// p_world = T_world_camera * p_camera.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace canopy {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec3f = Eigen::Vector3f;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using Pose = Eigen::Isometry3d;

/// Builds a pose from a translation and a (normalised) rotation.
inline Pose make_pose(const Vec3& t, const Quat& q) {
  Pose T = Pose::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

/// Planar pose of the mobile base in the world: x, y [m] and yaw [rad].
struct BasePose {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

/// Joint angles of the 6-DOF arm [rad], in the URDF's joint order.
constexpr int kArmDof = 6;
using ArmConfig = std::array<double, kArmDof>;

/// Wraps an angle to (-pi, pi].
double wrap_angle(double a);

/// Joint-space distance between two arm configurations (Euclidean, rad): ranks IK solutions,
/// orders views, measures arm paths.
double joint_distance(const ArmConfig& a, const ArmConfig& b);

}  // namespace canopy
