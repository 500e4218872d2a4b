#pragma once
// Job: which camera views around the plants the arm can reach from one base pose. What
// `canopy reach` does: the world's plants voxelised as the collision environment, a sphere of
// views around every fruit within reach, each tested for IK, collision and (optionally) a
// planned path from the start (motion/reachability.h); reach.json (the fractions, every
// sample, the settings used) and reach.png (a top and a side view of the views coloured by
// outcome) written into a folder.

#include <optional>
#include <string>

#include "canopy/common/image.h"
#include "canopy/motion/motion_config.h"
#include "canopy/motion/reachability.h"
#include "canopy/motion/robot_model.h"

namespace canopy::jobs {

/// What reach needs.
struct ReachJobParams {
  std::string world_file;
  motion::MotionConfig motion;               ///< The settings' motion section.
  BasePose base;
  std::optional<ArmConfig> joints;           ///< The arm at the start (default: home).
  std::string joints_where = "joints";       ///< Names the joints in a message ("--joints").
  motion::ReachParams grid;                  ///< The views around each fruit.
  double voxel_m = 0.015;                    ///< The voxels of the plants' occupancy, in [0.002, 0.2] m.
  std::string out;                           ///< Output folder (reach.json, reach.png).
};

/// What it found.
struct ReachJobResult {
  motion::ReachReport report;
  std::string start_collision;  ///< The first colliding pair when the start is in collision, else "".
};

/// The map of reach.png for a report: two panels side by side, a top view (x right, y up) and a
/// side view (y right, z up), 2.6 m wide, centred on the arm base: the plants' voxels, the
/// robot's box bodies at the start, the views coloured by outcome (planned on top) and their
/// targets. `legend` receives the colours (reach.json's "png").
Image<Rgb8> reach_map(const motion::ReachReport& report, const motion::RobotModel& robot, const ArmConfig& start,
                      const std::vector<Vec3>& plant_voxels, nlohmann::json* legend = nullptr);

/// Checks the parameters (InputError naming the bad one) before any work, evaluates the views
/// and publishes the folder.
ReachJobResult reach(const ReachJobParams& params);

}  // namespace canopy::jobs
