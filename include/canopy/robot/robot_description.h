#pragma once
// The robot's kinematic tree and geometry, read once from the URDF with urdfdom. The
// simulator builds its MuJoCo model from this, and motion planning computes kinematics and
// collision geometry from the same object, so both always agree.

#include <map>
#include <string>
#include <vector>

#include "canopy/common/types.h"

namespace canopy::robot {

enum class ShapeType { kBox, kSphere, kCylinder, kCapsule, kMesh };

/// A visual or collision shape attached to a link.
struct Shape {
  std::string name;
  ShapeType type = ShapeType::kBox;
  Vec3 box_size = Vec3::Zero();      ///< Full edge lengths (box).
  double radius = 0.0;               ///< Sphere, cylinder, capsule.
  double length = 0.0;               ///< Cylinder length; capsule: distance between cap centres.
  std::string mesh_file;             ///< Mesh path as written in the URDF.
  Vec3 mesh_scale = Vec3::Ones();
  Pose T_link_shape = Pose::Identity();  ///< Shape frame in the link frame; axis along z.
  float rgba[4] = {0.7f, 0.7f, 0.7f, 1.f};
};

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

/// A joint between a parent and a child link.
struct Joint {
  std::string name;
  JointType type = JointType::kFixed;
  std::string parent_link;
  std::string child_link;
  Pose T_parent_joint = Pose::Identity();  ///< Joint frame in the parent link frame.
  Vec3 axis = Vec3::UnitZ();               ///< Unit axis in the joint frame.
  double lower = 0.0, upper = 0.0;         ///< Position limits (none for continuous).
  double max_velocity = 0.0;
  double max_effort = 0.0;
  double damping = 0.0;
  bool movable() const { return type != JointType::kFixed; }
  bool limited() const { return type == JointType::kRevolute || type == JointType::kPrismatic; }
  /// Child link frame in the parent link frame at position q.
  Pose transform(double q) const;
};

/// A link with its inertia and shapes.
struct Link {
  std::string name;
  int parent_joint = -1;                ///< Index into joints(), -1 for the root.
  double mass = 0.0;
  Vec3 com = Vec3::Zero();              ///< Centre of mass in the link frame.
  Mat3 inertia = Mat3::Zero();          ///< About the centre of mass, link axes.
  std::vector<Shape> visuals;
  std::vector<Shape> collisions;
};

/// Joint positions by joint name; joints not listed are at 0.
using JointPositions = std::map<std::string, double>;

/// The robot's tree, links in topological order (a parent before its children).
class RobotDescription {
 public:
  /// Reads a URDF; throws InputError naming the file on a parse error or an unsupported
  /// element. Collision cylinders named "*_capsule" become capsules.
  static RobotDescription load_urdf(const std::string& path);

  const std::string& name() const { return name_; }
  const std::vector<Link>& links() const { return links_; }
  const std::vector<Joint>& joints() const { return joints_; }
  /// Index of a link or joint; throws InputError when absent.
  int link_index(const std::string& name) const;
  int joint_index(const std::string& name) const;
  const Link& link(const std::string& name) const { return links_[static_cast<size_t>(link_index(name))]; }
  const Joint& joint(const std::string& name) const { return joints_[static_cast<size_t>(joint_index(name))]; }
  /// Parent link index of link `i` (-1 for the root).
  int parent_link(int i) const;

  /// Pose of `link` in the root frame.
  Pose link_pose(const std::string& link, const JointPositions& q) const;
  /// Poses of all links in the root frame, indexed like links().
  std::vector<Pose> link_poses(const JointPositions& q) const;
  /// Pose of `child` in the frame of its ancestor `ancestor`; throws if not an ancestor.
  Pose relative_pose(const std::string& ancestor, const std::string& child, const JointPositions& q) const;
  /// Largest |y| that the collision shapes of `link` reach in the link frame (for the base
  /// link: half the width of its footprint). 0 for a link without collision shapes.
  double collision_half_width_m(const std::string& link) const;
  /// Indices of the joints from the root down to `link`.
  std::vector<int> chain_to(const std::string& link) const;

 private:
  std::string name_;
  std::vector<Link> links_;
  std::vector<Joint> joints_;
  std::map<std::string, int> link_index_;
  std::map<std::string, int> joint_index_;
};

}  // namespace canopy::robot
