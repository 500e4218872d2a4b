#include "canopy/sim/scene_mjcf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <set>
#include <sstream>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"

namespace canopy::sim {

namespace {

using robot::JointType;
using robot::Link;
using robot::Shape;
using robot::ShapeType;

// Numbers in the scene: the shortest text that reads back as exactly `v`.
std::string num(double v) { return format_number(v, NumberFormat::kShortest); }
std::string rgb_text(double r, double g, double b) { return num(r) + " " + num(g) + " " + num(b); }
// The sun (world file `lighting`): the fixed sun, as always written, or the world seed's.
std::string sun_light(const world::WorldSpec& spec) {
  if (!spec.lighting.per_seed)
    return "    <light name=\"sun\" directional=\"true\" pos=\"0 0 5\" dir=\"-0.3 0.2 -1\" diffuse=\"0.55 0.55 0.55\" "
           "specular=\"0.05 0.05 0.05\" castshadow=\"true\"/>\n";
  Vec3 dir;
  double diffuse = 0.0;
  spec.lighting.sun(spec.seed, &dir, &diffuse);
  return "    <light name=\"sun\" directional=\"true\" pos=\"0 0 5\" dir=\"" + rgb_text(dir.x(), dir.y(), dir.z()) +
         "\" diffuse=\"" + rgb_text(diffuse, diffuse, diffuse) + "\" specular=\"0.05 0.05 0.05\" castshadow=\"true\"/>\n";
}
// Half the thickness of the concrete path's slab [m]: thin, but clear of the ground plane in depth.
constexpr double kPathHalfThicknessM = 0.002;
std::string vec3(const Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }
std::string quat(const Mat3& R) {
  const Quat q(R);
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}
std::string pose_attrs(const Pose& T) {
  return "pos=\"" + vec3(T.translation()) + "\" quat=\"" + quat(T.linear()) + "\"";
}

std::string shape_geom(const Shape& s, const Pose& T_body_shape) {
  std::string type, size;
  switch (s.type) {
    case ShapeType::kBox: type = "box"; size = vec3(0.5 * s.box_size); break;
    case ShapeType::kSphere: type = "sphere"; size = num(s.radius); break;
    case ShapeType::kCylinder: type = "cylinder"; size = num(s.radius) + " " + num(0.5 * s.length); break;
    case ShapeType::kCapsule: type = "capsule"; size = num(s.radius) + " " + num(0.5 * s.length); break;
    case ShapeType::kMesh:
      throw InputError("robot shape '" + s.name + "': mesh shapes are not supported in the generated scene yet");
  }
  return "type=\"" + type + "\" size=\"" + size + "\" " + pose_attrs(T_body_shape);
}

// Writes the robot as nested MuJoCo bodies: one body per movable joint; links attached by
// fixed joints are merged into the body that carries them (their frames become sites).
class RobotWriter {
 public:
  RobotWriter(const robot::RobotDescription& d, const RobotConfig& cfg, int robot_class, double fovy_deg,
              SceneDescription* scene)
      : d_(d), cfg_(cfg), robot_class_(robot_class), fovy_deg_(fovy_deg), scene_(scene) {}

  void write(std::ostream& os) {
    // Children of the root link that hang on fixed joints go into the world body.
    write_body_contents(os, 0, "    ", /*is_world=*/true);
  }

 private:
  // Links merged into the body whose frame is link `body_link`, with their transforms.
  void collect(int link, const Pose& T_body_link, std::vector<std::pair<int, Pose>>* merged,
               std::vector<int>* child_joints) const {
    merged->push_back({link, T_body_link});
    for (size_t ji = 0; ji < d_.joints().size(); ++ji) {
      const auto& j = d_.joints()[ji];
      if (j.parent_link != d_.links()[static_cast<size_t>(link)].name) continue;
      if (j.movable()) {
        child_joints->push_back(static_cast<int>(ji));
      } else {
        collect(d_.link_index(j.child_link), T_body_link * j.T_parent_joint, merged, child_joints);
      }
    }
  }

  void write_body_contents(std::ostream& os, int body_link, const std::string& ind, bool is_world) {
    std::vector<std::pair<int, Pose>> merged;
    std::vector<int> child_joints;
    collect(body_link, Pose::Identity(), &merged, &child_joints);
    // Inertia of everything merged, about the body origin, then at the combined COM.
    double mass = 0.0;
    Vec3 com = Vec3::Zero();
    for (const auto& [li, T] : merged) {
      const Link& l = d_.links()[static_cast<size_t>(li)];
      mass += l.mass;
      com += l.mass * (T * l.com);
    }
    if (!is_world) {
      if (mass <= 0.0) throw InputError(cfg_.urdf_path + ": moving link '" + d_.links()[static_cast<size_t>(body_link)].name + "' has no mass");
      com /= mass;
      Mat3 I = Mat3::Zero();
      for (const auto& [li, T] : merged) {
        const Link& l = d_.links()[static_cast<size_t>(li)];
        const Vec3 r = T * l.com - com;
        I += T.linear() * l.inertia * T.linear().transpose() + l.mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      }
      os << ind << "<inertial pos=\"" << vec3(com) << "\" mass=\"" << num(mass) << "\" fullinertia=\""
         << num(I(0, 0)) << " " << num(I(1, 1)) << " " << num(I(2, 2)) << " " << num(I(0, 1)) << " "
         << num(I(0, 2)) << " " << num(I(1, 2)) << "\"/>\n";
    }
    for (const auto& [li, T] : merged) {
      const Link& l = d_.links()[static_cast<size_t>(li)];
      if (is_world && li == body_link) continue;
      for (const auto& s : l.visuals) {
        const std::string name = kRobotPrefix + s.name;
        scene_->labels[name] = GeomLabel{robot_class_, kNoInstance, true};
        os << ind << "<geom name=\"" << name << "\" " << shape_geom(s, T * s.T_link_shape) << " group=\""
           << kGroupRobotVisual << "\" contype=\"0\" conaffinity=\"0\" rgba=\"" << s.rgba[0] << " " << s.rgba[1]
           << " " << s.rgba[2] << " " << s.rgba[3] << "\"/>\n";
      }
      for (const auto& s : l.collisions) {
        const std::string name = kRobotPrefix + s.name;
        scene_->labels[name] = GeomLabel{robot_class_, kNoInstance, true};
        os << ind << "<geom name=\"" << name << "\" " << shape_geom(s, T * s.T_link_shape) << " group=\""
           << kGroupRobotCollision << "\" contype=\"1\" conaffinity=\"1\" rgba=\"0.9 0.3 0.3 0.4\"/>\n";
      }
      os << ind << "<site name=\"" << frame_site_name(l.name) << "\" " << pose_attrs(T) << " size=\"0.005\" group=\"5\"/>\n";
      if (l.name == cfg_.camera_frame) {
        // MuJoCo cameras look along -z with y up; the optical frame looks along +z with y down.
        const Mat3 R = T.linear() * Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
        os << ind << "<camera name=\"" << kWristCameraName << "\" pos=\"" << vec3(T.translation()) << "\" quat=\""
           << quat(R) << "\" fovy=\"" << num(fovy_deg_) << "\"/>\n";
      }
    }
    for (int ji : child_joints) {
      const auto& j = d_.joints()[static_cast<size_t>(ji)];
      const int child = d_.link_index(j.child_link);
      Pose T_parent_link = Pose::Identity();
      for (const auto& [li, T] : merged)
        if (d_.links()[static_cast<size_t>(li)].name == j.parent_link) T_parent_link = T;
      os << ind << "<body name=\"" << kRobotPrefix << j.child_link << "\" " << pose_attrs(T_parent_link * j.T_parent_joint)
         << ">\n";
      const std::string jind = ind + "  ";
      os << jind << "<joint name=\"" << kRobotPrefix << j.name << "\" type=\""
         << (j.type == JointType::kPrismatic ? "slide" : "hinge") << "\" axis=\"" << vec3(j.axis) << "\"";
      if (j.limited()) os << " limited=\"true\" range=\"" << num(j.lower) << " " << num(j.upper) << "\"";
      os << " damping=\"" << num(j.damping) << "\" armature=\"" << num(armature(j.name)) << "\"/>\n";
      write_body_contents(os, child, jind, false);
      os << ind << "</body>\n";
    }
  }

  double armature(const std::string& joint) const {
    for (int i = 0; i < kArmDof; ++i)
      if (cfg_.arm_joints[static_cast<size_t>(i)] == joint) return cfg_.arm_armature[static_cast<size_t>(i)];
    return 0.0;
  }

 private:
  const robot::RobotDescription& d_;
  const RobotConfig& cfg_;
  int robot_class_;
  double fovy_deg_;
  SceneDescription* scene_;
};

void write_mesh_asset(std::ostream& os, const std::string& name, const world::TriMesh& mesh) {
  os << "    <mesh name=\"" << name << "\" vertex=\"";
  for (const auto& v : mesh.vertices) os << vec3(v) << ' ';
  os << "\" face=\"";
  for (const auto& f : mesh.faces) os << f[0] << " " << f[1] << " " << f[2] << " ";
  os << "\"/>\n";
}

// A textured mesh: MuJoCo 2.2.2 takes one texture coordinate per vertex, so a vertex is
// repeated for every distinct texture coordinate its faces give it. MuJoCo's textures start
// at the image's top row, the coordinates' v = 0 at its bottom: v is written as 1 - v.
void write_textured_mesh_asset(std::ostream& os, const std::string& name, const world::TriMesh& mesh,
                               const std::vector<world::FaceUv>& uv) {
  CANOPY_CHECK(uv.size() == mesh.faces.size(), "a textured part has one texture coordinate triple per face");
  std::map<std::tuple<int, double, double>, int> index;
  std::vector<std::pair<int, Vec2>> corners;
  std::vector<std::array<int, 3>> faces;
  for (size_t k = 0; k < mesh.faces.size(); ++k) {
    std::array<int, 3> f{};
    for (size_t c = 0; c < 3; ++c) {
      const int v = mesh.faces[k][c];
      const Vec2 t = uv[k][c];
      const auto [it, fresh] = index.try_emplace({v, t.x(), t.y()}, static_cast<int>(corners.size()));
      if (fresh) corners.push_back({v, t});
      f[c] = it->second;
    }
    faces.push_back(f);
  }
  os << "    <mesh name=\"" << name << "\" vertex=\"";
  for (const auto& [v, t] : corners) os << vec3(mesh.vertices[static_cast<size_t>(v)]) << ' ';
  os << "\" texcoord=\"";
  for (const auto& [v, t] : corners) os << num(t.x()) << ' ' << num(1.0 - t.y()) << ' ';
  os << "\" face=\"";
  for (const auto& f : faces) os << f[0] << " " << f[1] << " " << f[2] << " ";
  os << "\"/>\n";
}

// A mesh of the scene: one plant part, or with merging, a plant's untextured parts of one class
// and colour that are no fruit instance (its petioles, its stems), as one mesh named after the
// first of them. MuJoCo 2.2.2's compiler finds each geom's mesh by a scan of every mesh's name,
// so a model's compile is quadratic in its meshes (a compartment window's 23 k parts); merging
// halves them, and changes neither a pixel's class nor its colour.
struct DrawnPart {
  std::string name;
  const world::PlantPart* part = nullptr;  // the first (its colour, class, texture)
  std::optional<world::TriMesh> merged;    // empty: the part's own mesh
  const world::TriMesh& mesh() const { return merged ? *merged : part->mesh; }
};

std::vector<DrawnPart> drawn_parts(const std::vector<std::shared_ptr<const world::Plant>>& plants, bool merge) {
  std::vector<DrawnPart> out;
  for (const auto& plant : plants) {
    std::map<std::array<std::uint32_t, 4>, std::size_t> group_of;  // class and colour bits -> entry in `out`
    for (const auto& part : plant->parts) {
      if (!merge || part.texture || part.instance_id != kNoInstance) {
        out.push_back(DrawnPart{part.name, &part, std::nullopt});
        continue;
      }
      std::array<std::uint32_t, 4> key{static_cast<std::uint32_t>(part.class_id), 0, 0, 0};
      for (int c = 0; c < 3; ++c) std::memcpy(&key[static_cast<std::size_t>(c) + 1], &part.rgba[c], sizeof(float));
      const auto [it, fresh] = group_of.try_emplace(key, out.size());
      if (fresh) {
        out.push_back(DrawnPart{part.name, &part, std::nullopt});
        continue;
      }
      DrawnPart& d = out[it->second];
      if (!d.merged) {  // a second part: the group becomes a merged mesh
        d.merged = d.part->mesh;
        d.name += "_merged";
      }
      d.merged->append(part.mesh);
    }
  }
  return out;
}

}  // namespace

std::string frame_site_name(const std::string& link) { return std::string(kRobotPrefix) + "frame/" + link; }

SceneDescription make_scene_mjcf(const world::World& world, const robot::RobotDescription& robot,
                                 const RobotConfig& cfg, const SceneOptions& options) {
  const world::WorldSpec& spec = world.spec;
  const world::GroundLook& g = spec.ground;
  SceneDescription scene;
  scene.has_robot = true;
  const double extent = 2.0;  // fixes MuJoCo's relative znear/zfar; see Renderer::depth_from_buffer
  std::ostringstream os;
  os << "<mujoco model=\"canopy_" << spec.name << "\">\n"
     << "  <!-- Generated by canopy from " << (spec.source_file.empty() ? "a world spec" : spec.source_file)
     << " (seed " << spec.seed << ") and " << cfg.urdf_path << ". Do not edit. -->\n"
     << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
     << "  <option timestep=\"" << num(options.timestep_s) << "\" integrator=\"implicit\"/>\n"
     << "  <statistic extent=\"" << num(extent) << "\" center=\"" << num(spec.rows.x_start_m) << " 0 0.6\"/>\n"
     << "  <visual>\n"
     << "    <global offwidth=\"" << std::max(spec.camera.width_px, options.min_offscreen_width_px) << "\" offheight=\""
     << std::max(spec.camera.height_px, options.min_offscreen_height_px) << "\"/>\n"
     << "    <quality shadowsize=\"2048\" offsamples=\"0\"/>\n"
     << "    <map znear=\"" << num(options.znear_m / extent) << "\" zfar=\"" << num(options.zfar_m / extent) << "\"/>\n"
     << "    <headlight ambient=\"0.35 0.35 0.35\" diffuse=\"0.45 0.45 0.45\" specular=\"0.05 0.05 0.05\"/>\n"
     << "  </visual>\n"
     << "  <asset>\n"
     << "    <texture name=\"sky\" type=\"skybox\" builtin=\"gradient\" rgb1=\"0.75 0.85 0.95\" rgb2=\"0.95 0.95 0.95\" width=\"64\" height=\"64\"/>\n"
     << "    <material name=\"ground\" rgba=\"" << rgb_text(g.film_r, g.film_g, g.film_b) << " 1\" specular=\"0\"/>\n"
     << "    <material name=\"ground_path\" rgba=\"" << rgb_text(g.path_r, g.path_g, g.path_b) << " 1\" specular=\"0\"/>\n"
     << "    <material name=\"heating_pipe\" rgba=\"" << rgb_text(g.pipe_r, g.pipe_g, g.pipe_b) << " 1\" specular=\"0.3\"/>\n"
     << "    <material name=\"plant\" specular=\"0.08\" shininess=\"0.1\"/>\n";
  // Plant textures: one texture and one material per texture file (shared by the parts and
  // the plants that use it).
  std::map<std::string, std::string> texture_of_file;
  const auto shown = [&](const world::Plant& plant) {
    return options.include_plants && plant.base_position.x() >= options.plants_from_x_m &&
           plant.base_position.x() < options.plants_to_x_m;
  };
  // The plants shown, with their parts (generated again when the world does not hold them).
  std::vector<std::shared_ptr<const world::Plant>> plants;
  for (std::size_t i = 0; i < world.plants.size(); ++i)
    if (shown(world.plants[i])) plants.push_back(world.plant(i));
  const std::vector<DrawnPart> drawn = drawn_parts(plants, options.merge_plant_parts);
  for (const DrawnPart& d : drawn) {
    const world::PlantPart& part = *d.part;
    if (part.texture) {
      auto [it, fresh] = texture_of_file.try_emplace(part.texture_file, "plant_tex_" + std::to_string(texture_of_file.size()));
      if (fresh) {
        os << "    <texture name=\"" << it->second << "\" type=\"2d\" file=\"textures/" << it->second << ".png\"/>\n"
           << "    <material name=\"" << it->second << "\" texture=\"" << it->second
           << "\" specular=\"0.08\" shininess=\"0.1\"/>\n";
        scene.files[it->second + ".png"] = part.texture_file;
      }
      write_textured_mesh_asset(os, part.name, part.mesh, part.uv);
    } else {
      write_mesh_asset(os, d.name, d.mesh());
    }
  }
  const bool windowed = std::isfinite(options.plants_from_x_m) && std::isfinite(options.plants_to_x_m);
  os << "  </asset>\n  <worldbody>\n"
     << sun_light(spec)
     << "    <geom name=\"ground\" type=\"plane\" size=\"30 30 0.1\""
     << (windowed ? " pos=\"" + num(0.5 * (options.plants_from_x_m + options.plants_to_x_m)) + " 0 0\"" : std::string())
     << " material=\"ground\" group=\"" << kGroupGround
     << "\" contype=\"1\" conaffinity=\"1\"/>\n";
  scene.labels["ground"] = GeomLabel{spec.class_of("ground"), kNoInstance, false};
  if (g.path_width_m > 0.0) {
    // The concrete path across the rows' start: a thin visual slab (the base rolls on the plane).
    const double x_hi = spec.rows.x_start_m - 0.5 * spec.rows.plant_spacing_m;
    const double half_y = spec.rows.row_offset_m + 1.0;
    os << "    <geom name=\"ground_path\" type=\"box\" size=\"" << num(0.5 * g.path_width_m) << " " << num(half_y) << " "
       << num(kPathHalfThicknessM) << "\" pos=\"" << num(x_hi - 0.5 * g.path_width_m) << " 0 " << num(kPathHalfThicknessM)
       << "\" material=\"ground_path\" group=\"" << kGroupGround << "\" contype=\"0\" conaffinity=\"0\"/>\n";
    scene.labels["ground_path"] = GeomLabel{spec.class_of("ground"), kNoInstance, false};
  }
  if (g.heating_pipes) {
    // A pair of pipes along every row, from half a spacing before its first plant to half a
    // spacing after its last; visual only (contype 0), like the plants.
    const double x0 = spec.rows.x_start_m - 0.5 * spec.rows.plant_spacing_m;
    const double x1 = spec.rows.x_start_m + spec.rows.plant_spacing_m * (spec.rows.plants_per_row - 0.5);
    for (int row = 0; row < spec.rows.rows; ++row) {
      const double y_row = row == 0 ? spec.rows.row_offset_m : -spec.rows.row_offset_m;
      for (int side = 0; side < 2; ++side) {
        const double y = y_row + (side == 0 ? -g.pipe_offset_m : g.pipe_offset_m);
        const std::string name = "heating_pipe_" + std::to_string(row) + "_" + std::to_string(side);
        os << "    <geom name=\"" << name << "\" type=\"capsule\" size=\"" << num(0.5 * g.pipe_diameter_m)
           << "\" fromto=\"" << num(x0) << " " << num(y) << " " << num(g.pipe_height_m) << " " << num(x1) << " " << num(y)
           << " " << num(g.pipe_height_m) << "\" material=\"heating_pipe\" group=\"" << kGroupGround
           << "\" contype=\"0\" conaffinity=\"0\"/>\n";
        scene.labels[name] = GeomLabel{spec.class_of("ground"), kNoInstance, false};
      }
    }
  }
  for (const DrawnPart& d : drawn) {
    const world::PlantPart& part = *d.part;
    if (part.texture)
      os << "    <geom name=\"" << d.name << "\" type=\"mesh\" mesh=\"" << d.name << "\" material=\""
         << texture_of_file.at(part.texture_file) << "\" group=\"" << kGroupPlants << "\" contype=\"0\" conaffinity=\"0\"/>\n";
    else
      os << "    <geom name=\"" << d.name << "\" type=\"mesh\" mesh=\"" << d.name << "\" material=\"plant\" rgba=\""
         << part.rgba[0] << " " << part.rgba[1] << " " << part.rgba[2] << " 1\" group=\"" << kGroupPlants
         << "\" contype=\"0\" conaffinity=\"0\"/>\n";
    scene.labels[d.name] = GeomLabel{part.class_id, part.instance_id, false};
  }
  RobotWriter(robot, cfg, spec.class_of("robot"), spec.camera.fovy_deg(), &scene).write(os);
  os << "  </worldbody>\n  <actuator>\n";
  const auto& bj = cfg.base_joints;
  for (int i = 0; i < 3; ++i) {
    const auto& j = robot.joint(bj[static_cast<size_t>(i)]);
    os << "    <velocity name=\"" << kRobotPrefix << j.name << "/vel\" joint=\"" << kRobotPrefix << j.name << "\" kv=\""
       << num(cfg.base_kv[static_cast<size_t>(i)]) << "\" forcelimited=\"true\" forcerange=\"" << num(-j.max_effort)
       << " " << num(j.max_effort) << "\"/>\n";
  }
  for (int i = 0; i < kArmDof; ++i) {
    const auto& j = robot.joint(cfg.arm_joints[static_cast<size_t>(i)]);
    os << "    <position name=\"" << kRobotPrefix << j.name << "/pos\" joint=\"" << kRobotPrefix << j.name << "\" kp=\""
       << num(cfg.arm_kp[static_cast<size_t>(i)]) << "\" forcelimited=\"true\" forcerange=\"" << num(-j.max_effort)
       << " " << num(j.max_effort) << "\"/>\n";
  }
  os << "  </actuator>\n";
  // Home keyframe: the base at the aisle start, the arm at home, servos holding home.
  // MuJoCo numbers joints in body order, which is the description's depth-first order.
  std::map<std::string, double> start{{bj[0], spec.robot_start.x_m}, {bj[1], spec.robot_start.y_m},
                                      {bj[2], spec.robot_start.yaw_rad}};
  for (int i = 0; i < kArmDof; ++i) start[cfg.arm_joints[static_cast<size_t>(i)]] = cfg.home[static_cast<size_t>(i)];
  os << "  <keyframe>\n    <key name=\"home\" qpos=\"";
  std::string sep;
  for (const auto& j : robot.joints())
    if (j.movable()) {
      os << sep << num(start.count(j.name) ? start.at(j.name) : 0.0);
      sep = " ";
    }
  os << "\" ctrl=\"0 0 0";
  for (double q : cfg.home) os << " " << num(q);
  os << "\"/>\n  </keyframe>\n</mujoco>\n";
  scene.mjcf = os.str();
  return scene;
}

}  // namespace canopy::sim
