#pragma once
// Builds the MuJoCo scene (MJCF text) of a generated world with the robot: the robot's
// bodies, joints, geoms and wrist camera come from the RobotDescription (the URDF), the
// plants from the world's meshes. Also records each geom's semantic class and instance.

#include <limits>
#include <map>
#include <string>

#include "canopy/common/frame.h"
#include "canopy/robot/robot_config.h"
#include "canopy/robot/robot_description.h"
#include "canopy/world/world.h"

namespace canopy::sim {

/// Semantic label of a geom.
struct GeomLabel {
  int class_id = 0;
  int instance_id = kNoInstance;
  bool robot = false;  ///< A geom of the robot itself.
};

/// Geom groups used in generated scenes (mjvOption::geomgroup).
enum GeomGroup { kGroupGround = 0, kGroupPlants = 1, kGroupRobotVisual = 2, kGroupRobotCollision = 3 };

/// MJCF text plus the labels of its named geoms. Unnamed or unlisted geoms are background.
struct SceneDescription {
  std::string mjcf;
  std::map<std::string, GeomLabel> labels;
  bool has_robot = false;
  /// Files the MJCF names (plant textures, file="textures/NAME"): NAME -> the file on disk.
  /// The simulator hands them to MuJoCo in memory; `canopy world` copies them beside scene.xml.
  std::map<std::string, std::string> files;
};

/// Name of the MuJoCo camera on the wrist and of the sites marking robot frames.
constexpr const char* kWristCameraName = "wrist_camera";
std::string frame_site_name(const std::string& link);
/// Prefix of every robot geom, joint and body name in the generated scene.
constexpr const char* kRobotPrefix = "robot/";

/// Simulation settings written into the scene.
struct SceneOptions {
  double timestep_s = 0.002;
  double znear_m = 0.02;   ///< Near clipping plane (must be below the camera's min range).
  double zfar_m = 20.0;
  /// Plant meshes in the scene. The simulator steps a model without them (they never
  /// collide, yet MuJoCo 2.2.2 walks every geom in each step) and renders one with them.
  bool include_plants = true;
  /// Only the plants whose base x lies in [plants_from_x_m, plants_to_x_m): a window of a long
  /// row's plants (Simulator's plant sections). With a bounded window the ground plane is
  /// centred on it (the plane is drawn 30 m either way). Unbounded, the default: every plant,
  /// and the scene as it always was.
  double plants_from_x_m = -std::numeric_limits<double>::infinity();
  double plants_to_x_m = std::numeric_limits<double>::infinity();
  /// Each plant's untextured parts of one class and colour that are no fruit instance (its
  /// petioles, its stems) drawn as one mesh: the same classes and colours, about half the
  /// meshes (MuJoCo 2.2.2's compile is quadratic in them: a compartment window's compile about
  /// half the CPU, docs/performance.md). Vertices are re-centred per mesh in floats, so a pixel
  /// may differ from the unmerged scene's by a rounding (none did in the test's 640,000). Off:
  /// the scene as it always was; the Simulator's windows of a long row are always merged.
  bool merge_plant_parts = false;
  /// The rendered model per section (issue 49; Simulator): plants are grouped by their base x
  /// in sections of plant_section_m from the first plant's, and with plant_window_m > 0 the
  /// rendered model holds only the sections of one window (plant_window_m long, at least the
  /// sections needed) around the robot; Simulator::show_plants_near moves it. The sections
  /// needed for a base at x are those within plant_reach_m plus the camera's max range of x.
  /// A world whose plants fit in one window, or of fewer than plant_window_min_triangles
  /// triangles (every world file but the compartment's, and the default world's rows made 100
  /// plants long), is built whole, as without a window. 0: no window.
  double plant_window_m = 0.0;
  double plant_window_min_triangles = 3.0e6;
  /// Without a window, a scene of every plant of more triangles than this is refused
  /// (InputError) instead of compiled: MuJoCo 2.2.2's compiler takes minutes and gigabytes for
  /// more (the compartment's 23 M did not load in 11 min at 4.6 GB). Commands that follow the
  /// robot along a long row (canopy mission, canopy bench mission) build windows instead.
  double whole_max_triangles = 6.0e6;
  double plant_section_m = 3.0;
  double plant_reach_m = 2.0;
  /// Smallest off-screen buffer (for larger video frames than the camera's).
  int min_offscreen_width_px = 640;
  int min_offscreen_height_px = 480;
};

/// The full scene: ground, lights, plants, robot, actuators and the home keyframe.
SceneDescription make_scene_mjcf(const world::World& world, const robot::RobotDescription& robot,
                                 const RobotConfig& robot_config, const SceneOptions& options = {});

}  // namespace canopy::sim
