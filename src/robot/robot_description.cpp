#include "canopy/robot/robot_description.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <functional>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"

namespace canopy::robot {

namespace {

Pose to_pose(const urdf::Pose& p) {
  double qx, qy, qz, qw;
  p.rotation.getQuaternion(qx, qy, qz, qw);
  return make_pose(Vec3(p.position.x, p.position.y, p.position.z), Quat(qw, qx, qy, qz));
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Shape to_shape(const std::string& file, const std::string& link, const std::string& name,
               const urdf::GeometrySharedPtr& g, const urdf::Pose& origin, bool collision) {
  if (!g) throw InputError(file + ": link '" + link + "' has a shape without geometry");
  Shape s;
  s.name = name;
  s.T_link_shape = to_pose(origin);
  switch (g->type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(*g);
      s.type = ShapeType::kBox;
      s.box_size = Vec3(b.dim.x, b.dim.y, b.dim.z);
      break;
    }
    case urdf::Geometry::SPHERE:
      s.type = ShapeType::kSphere;
      s.radius = static_cast<const urdf::Sphere&>(*g).radius;
      break;
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(*g);
      s.type = collision && ends_with(name, "_capsule") ? ShapeType::kCapsule : ShapeType::kCylinder;
      s.radius = c.radius;
      s.length = c.length;
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(*g);
      s.type = ShapeType::kMesh;
      s.mesh_file = m.filename;
      s.mesh_scale = Vec3(m.scale.x, m.scale.y, m.scale.z);
      break;
    }
  }
  if (s.radius < 0.0 || s.length < 0.0 || (s.box_size.array() < 0.0).any())
    throw InputError(file + ": link '" + link + "' shape '" + name + "' has a negative size");
  return s;
}

}  // namespace

Pose Joint::transform(double q) const {
  Pose T = T_parent_joint;
  switch (type) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      T.rotate(Eigen::AngleAxisd(q, axis));
      break;
    case JointType::kPrismatic:
      T.translate(axis * q);
      break;
    case JointType::kFixed:
      break;
  }
  return T;
}

RobotDescription RobotDescription::load_urdf(const std::string& path) {
  const std::string xml = read_file(path);
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml);
  if (!model) throw InputError(path + ": not a valid URDF (urdfdom could not parse it)");
  RobotDescription d;
  d.name_ = model->getName();
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) throw InputError(path + ": URDF has no root link");

  // Depth-first traversal in child order gives a topological order.
  std::function<void(const urdf::LinkConstSharedPtr&, int)> visit = [&](const urdf::LinkConstSharedPtr& ul,
                                                                         int parent_joint) {
    Link link;
    link.name = ul->name;
    link.parent_joint = parent_joint;
    if (ul->inertial) {
      link.mass = ul->inertial->mass;
      const Pose T = to_pose(ul->inertial->origin);
      link.com = T.translation();
      Mat3 I;
      const auto& in = *ul->inertial;
      I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      link.inertia = T.linear() * I * T.linear().transpose();
      if (link.mass < 0.0) throw InputError(path + ": link '" + ul->name + "' has a negative mass");
    }
    int k = 0;
    for (const auto& v : ul->visual_array) {
      Shape s = to_shape(path, ul->name, v->name.empty() ? ul->name + "_visual_" + std::to_string(k) : v->name,
                         v->geometry, v->origin, false);
      if (v->material) {
        s.rgba[0] = v->material->color.r;
        s.rgba[1] = v->material->color.g;
        s.rgba[2] = v->material->color.b;
        s.rgba[3] = v->material->color.a;
      }
      link.visuals.push_back(s);
      ++k;
    }
    k = 0;
    for (const auto& c : ul->collision_array) {
      link.collisions.push_back(to_shape(
          path, ul->name, c->name.empty() ? ul->name + "_collision_" + std::to_string(k) : c->name, c->geometry,
          c->origin, true));
      ++k;
    }
    d.link_index_[link.name] = static_cast<int>(d.links_.size());
    d.links_.push_back(link);
    for (const auto& uj : ul->child_joints) {
      Joint j;
      j.name = uj->name;
      j.parent_link = uj->parent_link_name;
      j.child_link = uj->child_link_name;
      j.T_parent_joint = to_pose(uj->parent_to_joint_origin_transform);
      j.axis = Vec3(uj->axis.x, uj->axis.y, uj->axis.z);
      switch (uj->type) {
        case urdf::Joint::FIXED: j.type = JointType::kFixed; break;
        case urdf::Joint::REVOLUTE: j.type = JointType::kRevolute; break;
        case urdf::Joint::CONTINUOUS: j.type = JointType::kContinuous; break;
        case urdf::Joint::PRISMATIC: j.type = JointType::kPrismatic; break;
        default:
          throw InputError(path + ": joint '" + uj->name + "' has an unsupported type (use fixed, revolute, continuous or prismatic)");
      }
      if (j.movable()) {
        if (j.axis.norm() < 1e-9) throw InputError(path + ": joint '" + j.name + "' has a zero axis");
        j.axis.normalize();
      }
      if (uj->limits) {
        j.lower = uj->limits->lower;
        j.upper = uj->limits->upper;
        j.max_velocity = uj->limits->velocity;
        j.max_effort = uj->limits->effort;
      }
      if (j.limited() && !(j.lower < j.upper))
        throw InputError(path + ": joint '" + j.name + "' needs lower < upper limits");
      if (uj->dynamics) j.damping = uj->dynamics->damping;
      const int ji = static_cast<int>(d.joints_.size());
      d.joint_index_[j.name] = ji;
      d.joints_.push_back(j);
      visit(model->getLink(uj->child_link_name), ji);
    }
  };
  visit(root, -1);
  return d;
}

int RobotDescription::link_index(const std::string& name) const {
  const auto it = link_index_.find(name);
  if (it == link_index_.end()) throw InputError("robot '" + name_ + "' has no link '" + name + "'");
  return it->second;
}

int RobotDescription::joint_index(const std::string& name) const {
  const auto it = joint_index_.find(name);
  if (it == joint_index_.end()) throw InputError("robot '" + name_ + "' has no joint '" + name + "'");
  return it->second;
}

int RobotDescription::parent_link(int i) const {
  const int pj = links_[static_cast<size_t>(i)].parent_joint;
  return pj < 0 ? -1 : link_index(joints_[static_cast<size_t>(pj)].parent_link);
}

double RobotDescription::collision_half_width_m(const std::string& link_name) const {
  double half_width = 0.0;
  for (const Shape& s : link(link_name).collisions) {
    Vec3 half = Vec3::Zero();  // half extents in the shape frame (axis along z)
    switch (s.type) {
      case ShapeType::kBox: half = 0.5 * s.box_size; break;
      case ShapeType::kSphere: half = Vec3::Constant(s.radius); break;
      case ShapeType::kCylinder: half = Vec3(s.radius, s.radius, 0.5 * s.length); break;
      case ShapeType::kCapsule: half = Vec3(s.radius, s.radius, 0.5 * s.length + s.radius); break;
      case ShapeType::kMesh: throw InputError("collision_half_width_m: link '" + link_name + "' has a mesh collision shape");
    }
    // The shape's axis-aligned bounds in the link frame.
    const Vec3 extent = s.T_link_shape.linear().cwiseAbs() * half;
    const double y = s.T_link_shape.translation().y();
    half_width = std::max({half_width, std::abs(y + extent.y()), std::abs(y - extent.y())});
  }
  return half_width;
}

std::vector<int> RobotDescription::chain_to(const std::string& link) const {
  std::vector<int> chain;
  for (int li = link_index(link); links_[static_cast<size_t>(li)].parent_joint >= 0; li = parent_link(li))
    chain.push_back(links_[static_cast<size_t>(li)].parent_joint);
  std::reverse(chain.begin(), chain.end());
  return chain;
}

namespace {
double position_of(const JointPositions& q, const std::string& name) {
  const auto it = q.find(name);
  return it == q.end() ? 0.0 : it->second;
}
}  // namespace

Pose RobotDescription::link_pose(const std::string& link, const JointPositions& q) const {
  Pose T = Pose::Identity();
  for (int ji : chain_to(link)) {
    const Joint& j = joints_[static_cast<size_t>(ji)];
    T = T * j.transform(position_of(q, j.name));
  }
  return T;
}

std::vector<Pose> RobotDescription::link_poses(const JointPositions& q) const {
  std::vector<Pose> poses(links_.size(), Pose::Identity());
  for (size_t i = 0; i < links_.size(); ++i) {
    const int pj = links_[i].parent_joint;
    if (pj < 0) continue;
    const Joint& j = joints_[static_cast<size_t>(pj)];
    poses[i] = poses[static_cast<size_t>(link_index(j.parent_link))] * j.transform(position_of(q, j.name));
  }
  return poses;
}

Pose RobotDescription::relative_pose(const std::string& ancestor, const std::string& child,
                                     const JointPositions& q) const {
  const int a = link_index(ancestor);
  Pose T = Pose::Identity();
  int li = link_index(child);
  while (li != a) {
    const int pj = links_[static_cast<size_t>(li)].parent_joint;
    if (pj < 0) throw InputError("link '" + ancestor + "' is not an ancestor of '" + child + "'");
    const Joint& j = joints_[static_cast<size_t>(pj)];
    T = j.transform(position_of(q, j.name)) * T;
    li = link_index(j.parent_link);
  }
  return T;
}

}  // namespace canopy::robot
