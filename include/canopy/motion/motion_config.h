#pragma once
// All motion settings in one place, read from configs/motion.yaml (every section and key
// optional; unknown keys are errors) and saved with each run's settings bundle.

#include <cstdint>
#include <string>

#include "canopy/robot/robot_config.h"
#include "canopy/common/params.h"
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
  /// Reads a motion.yaml over the defaults; throws InputError naming file and key.
  static MotionConfig load(const std::string& path, const RobotConfig& robot);
  /// Parses YAML text (tests); `name` stands in for the file name in errors.
  static MotionConfig load_string(const std::string& text, const std::string& name, const RobotConfig& robot);

  template <class A>
  void visit(A& a) {
    a("seed", seed, limits::non_negative(), "OMPL's process-wide seed (plans are seeded per request)");
    a.section("base", base, "The base follower");
    a.section("collision", collision, "Collision checking");
    a.section("planner", planner, "Arm motion planning (OMPL)");
    a.section("trajectory", trajectory, "Time parametrisation of arm paths");
    a.section("workspace", workspace, "The paper's workspace filter");
    a.section("tour", tour, "Ordering a batch of views");
    a.section("execution", execution, "Executing a move on the servos");
  }
};

}  // namespace canopy::motion
