#pragma once
// Job: the motion benchmark (`canopy bench motion`): IK time per solve on random poses,
// collision (validity) check time per state against a world's occupancy, and planning success
// rate and times to random reachable goals (targets: IK <= 2 us, >= 95 % success within 1 s).

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>

#include "canopy/motion/motion_config.h"

namespace canopy::jobs {

/// What bench_motion measures.
struct BenchMotionParams {
  std::string world_file = "worlds/default.yaml";
  motion::MotionConfig motion;  ///< The settings' motion section.
  BasePose base{0.75, 0.0, 0.0};  ///< For the collision and planning parts.
  int ik_poses = 100000;        ///< Random poses for the IK timing.
  int states = 20000;           ///< Random states for the validity timing.
  int goals = 100;              ///< Random reachable goals to plan to.
  std::uint64_t seed = 7;       ///< Of the random poses, states and goals.
};

/// What it measured (the keys of to_json() are those of `canopy bench motion --json`).
struct BenchMotionResult {
  // Kinematics.
  double ik_us = 0.0, camera_ik_us = 0.0, fk_us = 0.0;    ///< Per solve / call.
  double ik_solutions_per_pose = 0.0, camera_ik_solutions_per_pose = 0.0;
  double fk_checksum = 0.0;                               ///< Keeps the FK loop from being optimised away.
  // Validity checks.
  std::size_t map_voxels = 0;
  double map_resolution_m = 0.015;
  double validity_us = 0.0, validity_free_us = 0.0;       ///< Per state: random ones, collision-free ones.
  double colliding_fraction = 0.0;                        ///< Of the random states.
  std::size_t free_states_colliding = 0;                  ///< Collision-free states found colliding when timed again (0).
  // Planning.
  int goals = 0, planned = 0, direct = 0;                 ///< Goals, plans found, straight-line plans.
  double median_s = 0.0, p90_s = 0.0, max_s = 0.0;        ///< Times of the successful plans.
  std::map<std::string, int> statuses;                    ///< Every plan's status.
  std::string planner;                                    ///< OMPL's planner used.
  double time_limit_s = 0.0;                              ///< Its time limit per plan.
  nlohmann::json motion_config;                           ///< The motion settings used.

  /// The figures as `canopy bench motion --json` writes them.
  nlohmann::json to_json() const;
};

/// Runs the three measurements. InputError for a bad world file.
BenchMotionResult bench_motion(const BenchMotionParams& params);

}  // namespace canopy::jobs
