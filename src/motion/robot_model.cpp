#include "canopy/motion/robot_model.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"

namespace canopy::motion {

namespace {

constexpr int kBaseX = 6, kBaseY = 7, kBaseYaw = 8;

double bounding_radius(const robot::Shape& s) {
  switch (s.type) {
    case robot::ShapeType::kBox: return 0.5 * s.box_size.norm();
    case robot::ShapeType::kSphere: return s.radius;
    case robot::ShapeType::kCylinder: return std::hypot(s.radius, 0.5 * s.length);
    case robot::ShapeType::kCapsule: return 0.5 * s.length + s.radius;
    case robot::ShapeType::kMesh: break;
  }
  return 0.0;
}

}  // namespace

RobotModel RobotModel::load(const RobotConfig& config) {
  return RobotModel(robot::RobotDescription::load_urdf(config.urdf_path), config);
}

RobotModel::RobotModel(robot::RobotDescription description, const RobotConfig& config)
    : description_(std::move(description)), config_(config), ur_(UrDh::from_description(description_, config)) {
  const auto& links = description_.links();
  const auto& joints = description_.joints();
  const size_t n = links.size();
  joint_variable_.assign(n, -1);
  parent_link_.assign(n, -1);
  last_arm_joint_.assign(n, -1);
  collision_ancestor_.assign(n, -1);

  // Which variable drives each joint.
  std::vector<int> variable_of_joint(joints.size(), -1);
  for (int i = 0; i < kArmDof; ++i)
    variable_of_joint[static_cast<size_t>(description_.joint_index(config.arm_joints[static_cast<size_t>(i)]))] = i;
  for (int i = 0; i < 3; ++i) {
    const int ji = description_.joint_index(config.base_joints[static_cast<size_t>(i)]);
    variable_of_joint[static_cast<size_t>(ji)] = kBaseX + i;
  }
  for (size_t j = 0; j < joints.size(); ++j) {
    if (joints[j].movable() && variable_of_joint[j] < 0)
      throw InputError("robot '" + description_.name() + "': movable joint '" + joints[j].name +
                       "' is neither an arm joint nor a base joint in robot.yaml");
  }
  const robot::Joint& bx = description_.joint(config.base_joints[0]);
  const robot::Joint& by = description_.joint(config.base_joints[1]);
  const robot::Joint& byaw = description_.joint(config.base_joints[2]);
  if (bx.type != robot::JointType::kPrismatic || !bx.axis.isApprox(Vec3::UnitX()) ||
      by.type != robot::JointType::kPrismatic || !by.axis.isApprox(Vec3::UnitY()) || byaw.limited() ||
      !byaw.axis.isApprox(Vec3::UnitZ()))
    throw InputError("robot '" + description_.name() + "': base joints must be prismatic x, prismatic y, continuous yaw");
  base_link_ = description_.link_index(byaw.child_link);

  for (size_t i = 0; i < n; ++i) {
    const int pj = links[i].parent_joint;
    if (pj < 0) continue;
    const int parent = description_.parent_link(static_cast<int>(i));
    parent_link_[i] = parent;
    joint_variable_[i] = variable_of_joint[static_cast<size_t>(pj)];
    const int v = joint_variable_[i];
    last_arm_joint_[i] = (v >= 0 && v < kArmDof) ? v : last_arm_joint_[static_cast<size_t>(parent)];
    collision_ancestor_[i] = links[static_cast<size_t>(parent)].collisions.empty()
                                 ? collision_ancestor_[static_cast<size_t>(parent)]
                                 : parent;
  }

  // Arm limits: positions from the URDF, rates from robot.yaml.
  for (int i = 0; i < kArmDof; ++i) {
    const robot::Joint& j = description_.joint(config.arm_joints[static_cast<size_t>(i)]);
    limits_.lower[i] = j.limited() ? j.lower : -2.0 * M_PI;
    limits_.upper[i] = j.limited() ? j.upper : 2.0 * M_PI;
    limits_.max_velocity[i] = config.arm_max_velocity[i];
    limits_.max_acceleration[i] = config.arm_max_acceleration[i];
  }

  T_base_arm_ = description_.relative_pose(links[static_cast<size_t>(base_link_)].name, config.arm_base_frame, {});
  T_tool_camera_ = description_.relative_pose(config.tool_frame, config.camera_frame, {});
  T_camera_tool_ = T_tool_camera_.inverse(Eigen::Isometry);

  for (size_t i = 0; i < n; ++i) {
    for (const robot::Shape& s : links[i].collisions) {
      if (s.type == robot::ShapeType::kMesh)
        throw InputError("robot '" + description_.name() + "': collision shape '" + s.name +
                         "' is a mesh; motion planning needs boxes, spheres, cylinders or capsules");
      CollisionBody b;
      b.link = static_cast<int>(i);
      b.shape = s;
      b.bounding_radius_m = bounding_radius(s);
      b.on_arm = last_arm_joint_[i] >= 0;
      bodies_.push_back(b);
    }
  }
}

Pose RobotModel::T_world_base(const BasePose& base) {
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(base.yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  T.translation() = Vec3(base.x_m, base.y_m, 0.0);
  return T;
}

Pose RobotModel::camera_in_arm(const ArmConfig& q) const { return ur_.fk(q) * T_tool_camera_; }

Pose RobotModel::camera_pose(const BasePose& base, const ArmConfig& q) const {
  return T_world_base(base) * T_base_arm_ * camera_in_arm(q);
}

bool RobotModel::within_limits(const ArmConfig& q) const {
  for (int i = 0; i < kArmDof; ++i) {
    if (!std::isfinite(q[i]) || q[i] < limits_.lower[i] || q[i] > limits_.upper[i]) return false;
  }
  return true;
}

IkResult RobotModel::camera_ik(const BasePose& base, const Pose& T_world_camera, const ArmConfig& seed) const {
  const Pose T_world_arm = T_world_base(base) * T_base_arm_;
  return camera_ik_in_arm(T_world_arm.inverse(Eigen::Isometry) * T_world_camera, seed);
}

IkResult RobotModel::camera_ik_in_arm(const Pose& T_arm_camera, const ArmConfig& seed) const {
  IkResult out;
  for (int i = 0; i < kArmDof; ++i)
    if (!std::isfinite(seed[i])) return out;
  const Pose T06 = T_arm_camera * T_camera_tool_;
  const UrIkSolutions raw = ur_.ik(T06, seed[5]);
  std::array<double, 8> dist{};
  constexpr double kTwoPi = 2.0 * M_PI;
  for (int s = 0; s < raw.count; ++s) {
    ArmConfig q = raw.q[static_cast<size_t>(s)];
    bool ok = true;
    for (int i = 0; i < kArmDof && ok; ++i) {
      // The 2*pi equivalent nearest the seed; if that is out of limits, the next one
      // towards the allowed range (the nearest within limits).
      double v = q[i] + kTwoPi * std::nearbyint((seed[i] - q[i]) / kTwoPi);
      if (v < limits_.lower[i]) v += kTwoPi;
      else if (v > limits_.upper[i]) v -= kTwoPi;
      ok = v >= limits_.lower[i] && v <= limits_.upper[i];
      q[i] = v;
    }
    if (!ok) continue;
    double d2 = 0.0;
    for (int i = 0; i < kArmDof; ++i) d2 += (q[i] - seed[i]) * (q[i] - seed[i]);
    bool duplicate = false;
    for (int t = 0; t < out.count && !duplicate; ++t) {
      if (std::abs(dist[static_cast<size_t>(t)] - d2) > 1e-6) continue;  // cheap reject
      double m = 0.0;
      for (int i = 0; i < kArmDof; ++i) m = std::max(m, std::abs(out.q[static_cast<size_t>(t)][i] - q[i]));
      duplicate = m < 1e-9;
    }
    if (duplicate) continue;
    dist[static_cast<size_t>(out.count)] = d2;
    out.q[static_cast<size_t>(out.count++)] = q;
  }
  // Insertion sort by distance (at most 8 entries).
  for (int i = 1; i < out.count; ++i) {
    for (int j = i; j > 0 && dist[static_cast<size_t>(j)] < dist[static_cast<size_t>(j - 1)]; --j) {
      std::swap(dist[static_cast<size_t>(j)], dist[static_cast<size_t>(j - 1)]);
      std::swap(out.q[static_cast<size_t>(j)], out.q[static_cast<size_t>(j - 1)]);
    }
  }
  return out;
}

void RobotModel::link_poses(const BasePose& base, const ArmConfig& q, std::vector<Pose>* poses) const {
  const auto& links = description_.links();
  const auto& joints = description_.joints();
  poses->resize(links.size());
  (*poses)[0] = Pose::Identity();
  for (size_t i = 0; i < links.size(); ++i) {
    const int pj = links[i].parent_joint;
    if (pj < 0) {
      (*poses)[i] = Pose::Identity();
      continue;
    }
    const int v = joint_variable_[i];
    double value = 0.0;
    if (v >= 0 && v < kArmDof) value = q[static_cast<size_t>(v)];
    else if (v == kBaseX) value = base.x_m;
    else if (v == kBaseY) value = base.y_m;
    else if (v == kBaseYaw) value = base.yaw_rad;
    (*poses)[i] = (*poses)[static_cast<size_t>(parent_link_[i])] * joints[static_cast<size_t>(pj)].transform(value);
  }
}

void RobotModel::body_poses(const BasePose& base, const ArmConfig& q, std::vector<Pose>* poses) const {
  thread_local std::vector<Pose> links;
  link_poses(base, q, &links);
  poses->resize(bodies_.size());
  for (size_t b = 0; b < bodies_.size(); ++b)
    (*poses)[b] = links[static_cast<size_t>(bodies_[b].link)] * bodies_[b].shape.T_link_shape;
}

bool RobotModel::links_adjacent(int a, int b) const {
  if (a == b) return true;
  const size_t ua = static_cast<size_t>(a), ub = static_cast<size_t>(b);
  if (collision_ancestor_[ua] == b || collision_ancestor_[ub] == a) return true;
  return last_arm_joint_[ua] == last_arm_joint_[ub];
}

}  // namespace canopy::motion
