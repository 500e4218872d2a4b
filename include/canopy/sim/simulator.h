#pragma once
// The MuJoCo simulation of a world with the robot: stepping, robot state and servo
// commands, and geom labels for rendering. Only sim/ and mission/ include MuJoCo.

#include <mujoco/mujoco.h>

#include <array>
#include <future>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "canopy/robot/robot_config.h"
#include "canopy/common/types.h"
#include "canopy/sim/scene_mjcf.h"

namespace canopy::sim {

/// Turns MuJoCo's fatal errors into exceptions (idempotent; called by Simulator).
void install_mujoco_error_handler();

/// A contact between a robot collision geom and another geom.
struct RobotContact {
  std::string robot_geom;
  std::string other_geom;
  bool self_collision = false;  ///< The other geom belongs to the robot too.
  double depth_m = 0.0;         ///< Penetration depth (positive when overlapping).
};

/// A copy of the simulation state, to go back to after a fault or to repeat a move: stepping
/// on from a restored snapshot gives the same states, bit for bit, as stepping on from where
/// it was taken. Besides MuJoCo's state it holds qfrc_bias, which the arm's gravity
/// compensation reads from the previous step.
struct SimState {
  double time = 0.0;
  std::vector<double> qpos, qvel, act, ctrl, qacc_warmstart, qfrc_bias;
};

/// The robot's links the scene keeps a frame of (every URDF link with a frame site), in the
/// URDF's order, each with its nearest ancestor that has one ("world" is the root), and their
/// world poses: the robot's state as a mission hands it to Python (on_view, on_state).
struct RobotLinks {
  std::vector<std::string> links;
  std::vector<std::string> parents;  ///< parents[i]: links[i]'s, "world" or an earlier link.
  std::vector<bool> fixed;           ///< The edge to the parent passes through fixed joints only (/tf_static).
  std::vector<Pose> poses;           ///< T_world_link of each link (its frame site).
};

/// Owns the MuJoCo models and data of a scene. With the robot in a generated world there are
/// two models: the stepped one holds the robot and the ground only (the plants never collide,
/// and in MuJoCo 2.2.2 they would cost ~90 % of every step), the rendered one holds everything
/// and follows the stepped one's joint positions (sync_render()).
class Simulator {
 public:
  /// Generates the scene of `world` with the robot and resets to the home keyframe.
  Simulator(const world::World& world, const RobotConfig& robot_config, const SceneOptions& options = {});
  /// Loads an arbitrary scene (analytic test scenes, no robot control).
  explicit Simulator(SceneDescription scene);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  /// The stepped model and its data.
  const mjModel* model() const { return model_.get(); }
  mjData* data() const { return data_.get(); }
  /// The rendered model (plants included) and its data, as of the last sync_render().
  const mjModel* render_model() const { return render_model_ ? render_model_.get() : model_.get(); }
  mjData* render_data() const { return render_data_ ? render_data_.get() : data_.get(); }
  /// Copies the joint positions into the rendered model and updates its kinematics.
  void sync_render();

  /// The rendered model per section (SceneOptions::plant_window_m; issue 49: a compartment's
  /// plants cannot be one compiled model). Makes the rendered model hold every plant section
  /// needed for a base anywhere in [base_x_lo_m, base_x_hi_m]; when the window it holds lacks
  /// one, the rendered model is built again for a new window (at least plant_window_m long,
  /// from the first section needed) and the robot's joint state carried over. Returns whether
  /// it rebuilt. Without a window (none asked, or the world's plants fit in one) it does nothing.
  bool show_plants_near(double base_x_lo_m, double base_x_hi_m);
  /// Starts building, on another thread, the rendered model that show_plants_near(lo, hi)
  /// would build, so that the call finds it built (a compartment's window takes seconds to
  /// compile). The model is the same either way, bit for bit; until it is taken (or another
  /// is asked for) two rendered models are held. Returns whether it started one: not without
  /// a window, nor when the window held covers [lo, hi], nor when that build is under way.
  bool prepare_plants_near(double base_x_lo_m, double base_x_hi_m);
  /// Whether the rendered model holds every plant section needed for a base in [lo, hi] (no rebuild).
  bool holds_plants_near(double base_x_lo_m, double base_x_hi_m) const;
  /// The base x range of the window prepare_plants_near is building, [from, to); (0, 0) when none.
  std::pair<double, double> prepared_plant_window_x() const;
  /// Whether the rendered model holds a window of the plants rather than all of them.
  bool plants_windowed() const { return world_ != nullptr; }
  /// The sections of plants the rendered model holds: [first, end) of `plant_sections()`.
  std::pair<int, int> plant_window() const { return {window_first_, window_end_}; }
  int plant_sections() const { return sections_; }
  /// The base x range of the plants the rendered model holds, [from, to); unbounded without a window.
  std::pair<double, double> plant_window_x() const;
  /// Counts the rendered model's rebuilds (renderers follow it on their next frame).
  int render_generation() const { return render_generation_; }
  /// Labels are indexed by the rendered model's geom ids. The MJCF text is not kept once
  /// compiled (`mjcf` is empty): it writes every plant vertex out as numbers, and a long row's
  /// would be held for the whole mission (make_scene_mjcf gives it again).
  const SceneDescription& scene() const { return scene_; }
  /// Label of MuJoCo geom `geom_id` (background when unlabelled).
  const GeomLabel& geom_label(int geom_id) const { return geom_labels_[static_cast<size_t>(geom_id)]; }
  bool has_robot() const { return scene_.has_robot; }
  const RobotConfig& robot_config() const { return robot_config_; }

  /// Resets time, velocities and servo targets; the base at the world's start, arm at home.
  void reset_home();
  /// Teleports the robot (zero velocities; servo targets = q) and updates kinematics.
  void set_robot_state(const BasePose& base, const ArmConfig& q);
  BasePose base_pose() const;
  ArmConfig arm_positions() const;
  /// Position-servo set points of the arm.
  void set_arm_targets(const ArmConfig& q);
  /// Differential-drive command: forward speed along the heading and yaw rate.
  void set_base_velocity(double v_m_s, double omega_rad_s);
  /// Advances `n` steps (gravity compensation applied to the arm when configured).
  void step(int n = 1);
  /// False when the state is not finite or MuJoCo flagged a bad position, velocity or
  /// acceleration since the last snapshot or restore (MuJoCo then resets the data itself).
  bool state_ok() const;
  /// The current state (for restore()).
  SimState snapshot() const;
  /// Goes back to a snapshot (and clears MuJoCo's warning counters).
  void restore(const SimState& state);
  double time() const { return data_->time; }
  double timestep() const { return model_->opt.timestep; }
  /// Recomputes positions-dependent quantities (kinematics, cameras) for the current qpos.
  void update_kinematics();
  /// T_world_camera of the wrist camera (optical frame: x right, y down, z forward), as the
  /// kinematics last computed it: after step() that is the state before the step's integration
  /// (MuJoCo's positions-dependent quantities lag qpos by a step) until update_kinematics().
  Pose camera_pose() const;
  /// World pose of a robot link (its frame site).
  Pose frame_pose(const std::string& link) const;
  /// Contacts of robot collision geoms in the current state.
  std::vector<RobotContact> robot_contacts() const;
  /// The robot's link tree and its links' world poses now (empty without a robot).
  RobotLinks robot_links() const;

 private:
  struct ModelDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
  };
  struct DataDeleter {
    void operator()(mjData* d) const { mj_deleteData(d); }
  };
  using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
  // A compiled rendered model of a window, with its scene's labels and files.
  struct CompiledWindow {
    ModelPtr model;
    std::map<std::string, GeomLabel> labels;
    std::map<std::string, std::string> files;
  };
  // mjcf compiled, with `files` in MuJoCo's in-memory file system. Any thread.
  static ModelPtr compile(const std::string& mjcf, const std::map<std::string, std::string>& files);
  void load(const std::string& mjcf);
  void load_render(const std::string& mjcf);
  // geom_labels_ of `m` from scene_.labels.
  void label_geoms(const mjModel* m);
  // The sections [first, end) for a base anywhere in [lo, hi]; (-1, -1) when the window held covers them.
  std::pair<int, int> window_for(double base_x_lo_m, double base_x_hi_m) const;
  double section_x(int section) const;
  // The rendered model of the plant sections [first, end): reads only what the constructor
  // set (the world, options, robot), so it runs on prepare_plants_near's thread too.
  CompiledWindow compile_window(int first, int end) const;
  // Builds (or takes the prepared) rendered model of the plant sections [first, end).
  void build_window(int first, int end);
  // Frees the compiled scene's MJCF text (scene().mjcf).
  void release_mjcf();
  void bind_robot();
  int require_id(int type, const std::string& name) const;

  SceneDescription scene_;
  RobotConfig robot_config_;
  SceneOptions options_;
  // Windowed scenes only (else null): the world, which the caller keeps alive, and its sections.
  const world::World* world_ = nullptr;
  double sections_x0_m_ = 0.0;
  int sections_ = 1, window_first_ = 0, window_end_ = 1;
  int sections_per_window_ = 1;  // plant_window_m / plant_section_m, at least 1
  int render_generation_ = 0;
  BasePose start_;
  RobotLinks link_tree_;  // robot_links() without the poses, found once
  std::unique_ptr<mjModel, ModelDeleter> model_;
  std::unique_ptr<mjData, DataDeleter> data_;
  std::unique_ptr<mjModel, ModelDeleter> render_model_;  // null: render model_ itself
  std::unique_ptr<mjData, DataDeleter> render_data_;
  std::vector<GeomLabel> geom_labels_;
  // Robot bindings (indices into qpos / qvel / ctrl).
  std::array<int, 3> base_qpos_{}, base_dof_{}, base_act_{};
  std::array<int, kArmDof> arm_qpos_{}, arm_dof_{}, arm_act_{};
  int camera_id_ = -1;
  // prepare_plants_near's build: sections [first, end). Last member: destroyed first, it waits
  // for its thread, which reads the members above.
  struct Prepared {
    int first = -1, end = -1;
    std::future<CompiledWindow> built;
  };
  Prepared prepared_;
};

}  // namespace canopy::sim
