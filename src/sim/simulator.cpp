#include "canopy/sim/simulator.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <future>
#include <map>
#include <limits>
#include <tuple>
#include <mutex>
#include <stdexcept>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"

namespace canopy::sim {

namespace {

[[noreturn]] void throw_mujoco_error(const char* msg) { throw std::runtime_error(std::string("MuJoCo: ") + msg); }
void log_mujoco_warning(const char* msg) { spdlog::warn("MuJoCo: {}", msg); }

Pose pose_from_mj(const mjtNum* pos, const mjtNum* mat) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(pos[0], pos[1], pos[2]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = mat[3 * r + c];
  return T;
}

bool starts_with(const char* s, const char* prefix) { return s && std::strncmp(s, prefix, std::strlen(prefix)) == 0; }

}  // namespace

void install_mujoco_error_handler() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = throw_mujoco_error;
    mju_user_warning = log_mujoco_warning;
  });
}

Simulator::Simulator(const world::World& world, const RobotConfig& robot_config, const SceneOptions& options)
    : robot_config_(robot_config), options_(options), start_(world.spec.robot_start) {
  const robot::RobotDescription description = robot::RobotDescription::load_urdf(robot_config.urdf_path);
  // Plant sections: by base x, plant_section_m long from the first plant's.
  if (options.include_plants && options.plant_window_m > 0.0 && !world.plants.empty()) {
    CANOPY_CHECK(options.plant_section_m > 0.0 && options.plant_reach_m >= 0.0, "plant sections need a positive length");
    double x0 = world.plants.front().base_position.x(), x1 = x0;
    for (const world::Plant& p : world.plants) {
      x0 = std::min(x0, p.base_position.x());
      x1 = std::max(x1, p.base_position.x());
    }
    const int sections = static_cast<int>(std::floor((x1 - x0) / options.plant_section_m)) + 1;
    const int per_window = std::max(1, static_cast<int>(std::lround(options.plant_window_m / options.plant_section_m)));
    if (sections > per_window && static_cast<double>(world.triangle_count()) >= options.plant_window_min_triangles) {
      // else the whole world: today's scene
      world_ = &world;
      sections_x0_m_ = x0;
      sections_ = sections;
      sections_per_window_ = per_window;
      window_end_ = 0;  // nothing held yet
    }
  }
  const bool every_plant = std::isinf(options.plants_from_x_m) && options.plants_from_x_m < 0.0 &&
                           std::isinf(options.plants_to_x_m) && options.plants_to_x_m > 0.0;
  if (!world_ && options.include_plants && every_plant &&
      static_cast<double>(world.triangle_count()) > options.whole_max_triangles)
    throw InputError("world '" + world.spec.name + "': " + std::to_string(world.triangle_count()) +
                     " plant triangles, more than one rendered model of the whole world holds (" +
                     std::to_string(static_cast<long long>(options.whole_max_triangles)) +
                     "); canopy mission and canopy bench mission render it a window at a time, this command cannot");
  if (world_) {
    SceneOptions physics = options;
    physics.include_plants = false;
    scene_ = make_scene_mjcf(world, description, robot_config, physics);
    load(scene_.mjcf);
    release_mjcf();
    show_plants_near(start_.x_m, start_.x_m);
  } else {
    scene_ = make_scene_mjcf(world, description, robot_config, options);
    if (options.include_plants && !world.plants.empty()) {
      SceneOptions physics = options;
      physics.include_plants = false;
      const SceneDescription stepped = make_scene_mjcf(world, description, robot_config, physics);
      load(stepped.mjcf);
      load_render(scene_.mjcf);
      CANOPY_CHECK(render_model_->nq == model_->nq && render_model_->nv == model_->nv,
                   "the rendered and the stepped scene differ in their joints");
    } else {
      load(scene_.mjcf);
    }
    release_mjcf();
  }
  bind_robot();
  // The link tree: each link with a frame site, under its nearest ancestor that has one.
  // fixed_below[i]: only fixed joints between link i and frame_of[i].
  std::vector<std::string> frame_of(description.links().size(), "world");
  std::vector<bool> fixed_below(description.links().size(), true);
  for (std::size_t i = 0; i < description.links().size(); ++i) {
    const std::string& name = description.links()[i].name;
    const int parent = description.parent_link(static_cast<int>(i));
    const std::string above = parent < 0 ? "world" : frame_of[static_cast<std::size_t>(parent)];
    const int joint = description.links()[i].parent_joint;
    const bool fixed = (joint < 0 || !description.joints()[static_cast<std::size_t>(joint)].movable()) &&
                       (parent < 0 || fixed_below[static_cast<std::size_t>(parent)]);
    const bool has_frame = name != "world" && mj_name2id(model_.get(), mjOBJ_SITE, frame_site_name(name).c_str()) >= 0;
    frame_of[i] = has_frame ? name : above;
    fixed_below[i] = has_frame || fixed;
    if (!has_frame) continue;
    link_tree_.links.push_back(name);
    link_tree_.parents.push_back(above);
    link_tree_.fixed.push_back(fixed);
  }
  reset_home();
}

Simulator::Simulator(SceneDescription scene) : scene_(std::move(scene)) {
  scene_.has_robot = false;
  load(scene_.mjcf);
  release_mjcf();
  mj_forward(model_.get(), data_.get());
}

Simulator::~Simulator() = default;

Simulator::ModelPtr Simulator::compile(const std::string& mjcf, const std::map<std::string, std::string>& files) {
  install_mujoco_error_handler();
  // The files added are freed however compile() ends.
  struct VfsFree {
    void operator()(mjVFS* v) const {
      mj_deleteVFS(v);
      delete v;
    }
  };
  std::unique_ptr<mjVFS, VfsFree> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* name = "canopy_scene.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(mjcf.size())) != 0)
    throw std::runtime_error("MuJoCo: cannot create the in-memory scene file");
  const int idx = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[idx], mjcf.data(), mjcf.size());
  // Files the scene names (plant textures), under the names it gives them.
  for (const auto& [file, disk_path] : files) {
    const std::string bytes = read_file(disk_path);
    if (mj_makeEmptyFileVFS(vfs.get(), file.c_str(), static_cast<int>(bytes.size())) != 0)
      throw std::runtime_error("MuJoCo: cannot add " + disk_path + " to the in-memory files");
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), file.c_str())], bytes.data(), bytes.size());
  }
  char error[1024] = "";
  ModelPtr model;
  {
    // MuJoCo 2.2's XML loader keeps global state (the last loaded model); load one at a time.
    static std::mutex load_mutex;
    std::lock_guard<std::mutex> lock(load_mutex);
    model.reset(mj_loadXML(name, vfs.get(), error, sizeof(error)));
  }
  if (!model) throw std::runtime_error(std::string("MuJoCo could not compile the scene: ") + error);
  return model;
}

void Simulator::load(const std::string& mjcf) {
  model_ = compile(mjcf, scene_.files);
  data_.reset(mj_makeData(model_.get()));
  label_geoms(model_.get());
}

void Simulator::label_geoms(const mjModel* m) {
  // Each geom's label by its name: one pass over the geoms (mj_name2id per label scans them
  // all, quadratic in a window's 23 k plant parts). MuJoCo's names are unique.
  geom_labels_.assign(static_cast<size_t>(m->ngeom), GeomLabel{});
  for (int id = 0; id < m->ngeom; ++id) {
    const auto it = scene_.labels.find(m->names + m->name_geomadr[id]);
    if (it != scene_.labels.end()) geom_labels_[static_cast<size_t>(id)] = it->second;
  }
}

void Simulator::release_mjcf() { std::string().swap(scene_.mjcf); }

void Simulator::load_render(const std::string& mjcf) {
  // load() into the stepped slots, then move the result over.
  auto stepped_model = std::move(model_);
  auto stepped_data = std::move(data_);
  load(mjcf);
  render_model_ = std::move(model_);
  render_data_ = std::move(data_);
  model_ = std::move(stepped_model);
  data_ = std::move(stepped_data);
}

std::pair<int, int> Simulator::window_for(double base_x_lo_m, double base_x_hi_m) const {
  const double margin = options_.plant_reach_m + world_->spec.camera.max_range_m;
  const auto section = [&](double x) {
    const double s = std::floor((x - sections_x0_m_) / options_.plant_section_m);
    return static_cast<int>(std::clamp(s, 0.0, static_cast<double>(sections_ - 1)));
  };
  const int first = section(std::min(base_x_lo_m, base_x_hi_m) - margin);
  const int last = section(std::max(base_x_lo_m, base_x_hi_m) + margin);
  if (first >= window_first_ && last < window_end_) return {-1, -1};
  const int count = std::max(sections_per_window_, last - first + 1);
  const int begin = std::max(0, std::min(first, sections_ - count));
  return {begin, std::min(sections_, begin + count)};
}

bool Simulator::show_plants_near(double base_x_lo_m, double base_x_hi_m) {
  if (!world_) return false;
  const auto [first, end] = window_for(base_x_lo_m, base_x_hi_m);
  if (first < 0) return false;
  build_window(first, end);
  return true;
}

bool Simulator::holds_plants_near(double base_x_lo_m, double base_x_hi_m) const {
  return !world_ || window_for(base_x_lo_m, base_x_hi_m).first < 0;
}

bool Simulator::prepare_plants_near(double base_x_lo_m, double base_x_hi_m) {
  if (!world_) return false;
  const auto [first, end] = window_for(base_x_lo_m, base_x_hi_m);
  if (first < 0 || (prepared_.built.valid() && prepared_.first == first && prepared_.end == end)) return false;
  if (prepared_.built.valid()) prepared_.built.wait();  // another window's: let it end, then drop it
  prepared_.first = first;
  prepared_.end = end;
  prepared_.built = std::async(std::launch::async, [this, first = first, end = end] { return compile_window(first, end); });
  return true;
}

double Simulator::section_x(int section) const { return sections_x0_m_ + section * options_.plant_section_m; }

std::pair<double, double> Simulator::plant_window_x() const {
  if (!world_) return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  return {section_x(window_first_), section_x(window_end_)};
}

std::pair<double, double> Simulator::prepared_plant_window_x() const {
  if (!prepared_.built.valid()) return {0.0, 0.0};
  return {section_x(prepared_.first), section_x(prepared_.end)};
}

Simulator::CompiledWindow Simulator::compile_window(int first, int end) const {
  SceneOptions window = options_;
  window.plants_from_x_m = section_x(first);
  window.plants_to_x_m = section_x(end);
  window.merge_plant_parts = true;  // a window's compile is quadratic in its meshes
  const robot::RobotDescription description = robot::RobotDescription::load_urdf(robot_config_.urdf_path);
  SceneDescription rendered = make_scene_mjcf(*world_, description, robot_config_, window);
  CompiledWindow out;
  out.model = compile(rendered.mjcf, rendered.files);
  out.labels = std::move(rendered.labels);
  out.files = std::move(rendered.files);
  return out;
}

void Simulator::build_window(int first, int end) {
  CompiledWindow built;
  if (prepared_.built.valid() && prepared_.first == first && prepared_.end == end) {
    built = prepared_.built.get();
  } else {
    if (prepared_.built.valid()) prepared_.built.wait();
    prepared_ = Prepared{};
    // Built here, the old model goes first: the two are never held at once.
    render_data_.reset();
    render_model_.reset();
    built = compile_window(first, end);
  }
  render_data_.reset();
  render_model_ = std::move(built.model);
  render_data_.reset(mj_makeData(render_model_.get()));
  window_first_ = first;
  window_end_ = end;
  // The labels of scene_ are the rendered scene's (the stepped one's are a subset).
  scene_.labels = std::move(built.labels);
  scene_.files = std::move(built.files);
  label_geoms(render_model_.get());
  CANOPY_CHECK(render_model_->nq == model_->nq && render_model_->nv == model_->nv,
               "the rendered and the stepped scene differ in their joints");
  ++render_generation_;
  sync_render();
}

void Simulator::sync_render() {
  if (!render_model_) return;
  mju_copy(render_data_->qpos, data_->qpos, model_->nq);
  render_data_->time = data_->time;
  mj_kinematics(render_model_.get(), render_data_.get());
  mj_camlight(render_model_.get(), render_data_.get());
}

bool Simulator::state_ok() const {
  for (int w : {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC, mjWARN_BADCTRL})
    if (data_->warning[w].number > 0) return false;
  for (int i = 0; i < model_->nq; ++i)
    if (!std::isfinite(data_->qpos[i])) return false;
  for (int i = 0; i < model_->nv; ++i)
    if (!std::isfinite(data_->qvel[i])) return false;
  return true;
}

SimState Simulator::snapshot() const {
  SimState s;
  s.time = data_->time;
  s.qpos.assign(data_->qpos, data_->qpos + model_->nq);
  s.qvel.assign(data_->qvel, data_->qvel + model_->nv);
  s.act.assign(data_->act, data_->act + model_->na);
  s.ctrl.assign(data_->ctrl, data_->ctrl + model_->nu);
  s.qacc_warmstart.assign(data_->qacc_warmstart, data_->qacc_warmstart + model_->nv);
  s.qfrc_bias.assign(data_->qfrc_bias, data_->qfrc_bias + model_->nv);
  return s;
}

void Simulator::restore(const SimState& s) {
  CANOPY_CHECK(int(s.qpos.size()) == model_->nq && int(s.qvel.size()) == model_->nv, "snapshot of another model");
  mj_resetData(model_.get(), data_.get());
  data_->time = s.time;
  std::copy(s.qpos.begin(), s.qpos.end(), data_->qpos);
  std::copy(s.qvel.begin(), s.qvel.end(), data_->qvel);
  std::copy(s.act.begin(), s.act.end(), data_->act);
  std::copy(s.ctrl.begin(), s.ctrl.end(), data_->ctrl);
  std::copy(s.qacc_warmstart.begin(), s.qacc_warmstart.end(), data_->qacc_warmstart);
  for (int w = 0; w < mjNWARNING; ++w) data_->warning[w].number = 0;
  mj_forward(model_.get(), data_.get());
  // mj_forward computed the bias forces of the restored positions; the next step's gravity
  // compensation reads those of the step before the snapshot.
  if (int(s.qfrc_bias.size()) == model_->nv) std::copy(s.qfrc_bias.begin(), s.qfrc_bias.end(), data_->qfrc_bias);
}

int Simulator::require_id(int type, const std::string& name) const {
  const int id = mj_name2id(model_.get(), static_cast<mjtObj>(type), name.c_str());
  if (id < 0)
    throw InputError("robot config: the scene has no " + std::string(mju_type2Str(type)) + " '" + name +
                     "' (check the joint and frame names in robot.yaml against the URDF)");
  return id;
}

void Simulator::bind_robot() {
  auto bind_joint = [&](const std::string& joint, int* qpos, int* dof) {
    const int j = require_id(mjOBJ_JOINT, kRobotPrefix + joint);
    *qpos = model_->jnt_qposadr[j];
    *dof = model_->jnt_dofadr[j];
  };
  for (int i = 0; i < 3; ++i) {
    const std::string& j = robot_config_.base_joints[static_cast<size_t>(i)];
    bind_joint(j, &base_qpos_[static_cast<size_t>(i)], &base_dof_[static_cast<size_t>(i)]);
    base_act_[static_cast<size_t>(i)] = require_id(mjOBJ_ACTUATOR, kRobotPrefix + j + "/vel");
  }
  for (int i = 0; i < kArmDof; ++i) {
    const std::string& j = robot_config_.arm_joints[static_cast<size_t>(i)];
    bind_joint(j, &arm_qpos_[static_cast<size_t>(i)], &arm_dof_[static_cast<size_t>(i)]);
    arm_act_[static_cast<size_t>(i)] = require_id(mjOBJ_ACTUATOR, kRobotPrefix + j + "/pos");
  }
  camera_id_ = require_id(mjOBJ_CAMERA, kWristCameraName);
}

void Simulator::reset_home() {
  CANOPY_CHECK(has_robot(), "reset_home on a scene without the robot");
  mj_resetData(model_.get(), data_.get());
  set_robot_state(start_, robot_config_.home);
}

void Simulator::set_robot_state(const BasePose& base, const ArmConfig& q) {
  CANOPY_CHECK(has_robot(), "set_robot_state on a scene without the robot");
  const double b[3] = {base.x_m, base.y_m, base.yaw_rad};
  for (int i = 0; i < 3; ++i) {
    data_->qpos[base_qpos_[static_cast<size_t>(i)]] = b[i];
    data_->ctrl[base_act_[static_cast<size_t>(i)]] = 0.0;
  }
  for (int i = 0; i < kArmDof; ++i) {
    data_->qpos[arm_qpos_[static_cast<size_t>(i)]] = q[static_cast<size_t>(i)];
    data_->ctrl[arm_act_[static_cast<size_t>(i)]] = q[static_cast<size_t>(i)];
  }
  mju_zero(data_->qvel, model_->nv);
  mju_zero(data_->qacc_warmstart, model_->nv);
  mj_forward(model_.get(), data_.get());
}

BasePose Simulator::base_pose() const {
  return BasePose{data_->qpos[base_qpos_[0]], data_->qpos[base_qpos_[1]], wrap_angle(data_->qpos[base_qpos_[2]])};
}

ArmConfig Simulator::arm_positions() const {
  ArmConfig q{};
  for (int i = 0; i < kArmDof; ++i) q[static_cast<size_t>(i)] = data_->qpos[arm_qpos_[static_cast<size_t>(i)]];
  return q;
}

void Simulator::set_arm_targets(const ArmConfig& q) {
  for (int i = 0; i < kArmDof; ++i) data_->ctrl[arm_act_[static_cast<size_t>(i)]] = q[static_cast<size_t>(i)];
}

void Simulator::set_base_velocity(double v_m_s, double omega_rad_s) {
  const double yaw = data_->qpos[base_qpos_[2]];
  data_->ctrl[base_act_[0]] = v_m_s * std::cos(yaw);
  data_->ctrl[base_act_[1]] = v_m_s * std::sin(yaw);
  data_->ctrl[base_act_[2]] = omega_rad_s;
}

void Simulator::step(int n) {
  for (int k = 0; k < n; ++k) {
    if (has_robot() && robot_config_.gravity_compensation) {
      // The arm controller cancels gravity and Coriolis forces, as UR controllers do, so the
      // position servos settle exactly. qfrc_bias is from the previous step's positions.
      mju_zero(data_->qfrc_applied, model_->nv);
      for (int i = 0; i < kArmDof; ++i) {
        const int dof = arm_dof_[static_cast<size_t>(i)];
        data_->qfrc_applied[dof] = data_->qfrc_bias[dof];
      }
    }
    mj_step(model_.get(), data_.get());
  }
}

void Simulator::update_kinematics() {
  mj_kinematics(model_.get(), data_.get());
  mj_comPos(model_.get(), data_.get());
  mj_camlight(model_.get(), data_.get());
  sync_render();
}

Pose Simulator::camera_pose() const {
  CANOPY_CHECK(camera_id_ >= 0, "scene has no wrist camera");
  // MuJoCo's camera frame looks along -z with y up; rotate to the optical convention.
  const Pose T_mj = pose_from_mj(data_->cam_xpos + 3 * camera_id_, data_->cam_xmat + 9 * camera_id_);
  Pose T = T_mj;
  T.linear() = T_mj.linear() * Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
  return T;
}

Pose Simulator::frame_pose(const std::string& link) const {
  const int site = require_id(mjOBJ_SITE, frame_site_name(link));
  return pose_from_mj(data_->site_xpos + 3 * site, data_->site_xmat + 9 * site);
}

RobotLinks Simulator::robot_links() const {
  RobotLinks out = link_tree_;
  for (const std::string& link : out.links) out.poses.push_back(frame_pose(link));
  return out;
}

std::vector<RobotContact> Simulator::robot_contacts() const {
  std::vector<RobotContact> out;
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    const char* n1 = mj_id2name(model_.get(), mjOBJ_GEOM, c.geom1);
    const char* n2 = mj_id2name(model_.get(), mjOBJ_GEOM, c.geom2);
    const bool r1 = starts_with(n1, kRobotPrefix), r2 = starts_with(n2, kRobotPrefix);
    if (!r1 && !r2) continue;
    RobotContact rc;
    rc.robot_geom = r1 ? n1 : n2;
    rc.other_geom = r1 ? (n2 ? n2 : "") : (n1 ? n1 : "");
    rc.self_collision = r1 && r2;
    rc.depth_m = -c.dist;
    out.push_back(rc);
  }
  return out;
}

}  // namespace canopy::sim
