#pragma once
// All motion settings in one place, read from configs/motion.yaml (every section and key
// optional; unknown keys are errors) and saved with each run as JSON.

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/motion/arm_planner.h"
#include "canopy/motion/base_follower.h"
#include "canopy/motion/collision.h"
#include "canopy/motion/execution.h"
#include "canopy/motion/tour.h"
#include "canopy/motion/trajectory.h"
#include "canopy/motion/workspace_filter.h"

namespace canopy::motion {

/// The motion module's settings.
struct MotionConfig {
  std::uint64_t seed = 1;  ///< OMPL's process-wide seed (see seed_planner_rng).
  BaseFollowerParams base;
  CollisionParams collision;
  PlannerParams planner;
  TrajectoryParams trajectory;
  WorkspaceParams workspace;
  TourParams tour;
  ExecutionParams execution;

  /// Defaults, with the base limits taken from robot.yaml.
  static MotionConfig defaults(const RobotConfig& robot);
  /// Reads one mapping (the keys of motion.yaml) over the defaults; rejects unknown keys.
  static MotionConfig from_yaml(YamlReader& y, const RobotConfig& robot);
  /// Reads a motion.yaml over the defaults; throws InputError naming file and key.
  static MotionConfig load(const std::string& path, const RobotConfig& robot);
  /// Parses YAML text (tests); `name` stands in for the file name in errors.
  static MotionConfig load_string(const std::string& text, const std::string& name, const RobotConfig& robot);
  /// The settings in use, for run records.
  nlohmann::json to_json() const;
};

}  // namespace canopy::motion
