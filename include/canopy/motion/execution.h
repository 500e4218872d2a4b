#pragma once
// Executing a planned arm trajectory on a simulator (or a robot) through its position
// servos, and judging the move: it succeeds when the camera ends within 1 cm and 2 degrees
// of the goal; contacts of the arm with the plants or itself during the move are counted.
//
// MuJoCo-free on purpose: execute_arm_move() is a template over any simulator offering
// set_arm_targets(q), step(), time(), camera_pose(), base_pose(), arm_positions() and
// robot_contacts() (elements with robot_geom, other_geom, self_collision, depth_m), which
// canopy::sim::Simulator does. The simulator's plant geoms may be contact-free (visual
// only), so arm-plant contacts can also be counted geometrically: pass a CollisionChecker
// built on the ground-truth geometry and every executed state is checked against it.

#include <cmath>
#include <set>
#include <string>

#include "canopy/common/params.h"
#include "canopy/common/types.h"
#include "canopy/motion/collision.h"
#include "canopy/motion/trajectory.h"

namespace canopy {
class YamlReader;
}

namespace canopy::motion {

/// Move execution settings (configs/motion.yaml, section "execution").
struct ExecutionParams {
  double position_tolerance_m = 0.01;                   ///< Camera goal tolerance (issue: 1 cm).
  double angle_tolerance_rad = 2.0 * M_PI / 180.0;      ///< Camera goal tolerance (issue: 2 deg).
  double settle_time_s = 1.0;                           ///< Extra time after the trajectory ends.
  double truth_check_period_s = 0.01;                   ///< Ground-truth contact check interval.

  template <class A>
  void visit(A& a) {
    a("position_tolerance_m", position_tolerance_m, limits::positive(), "Camera goal tolerance [m]");
    a("angle_tolerance_rad", angle_tolerance_rad, limits::positive(), "Camera goal tolerance [rad]");
    a("settle_time_s", settle_time_s, limits::non_negative(), "Extra time after the trajectory ends [s]");
    a("truth_check_period_s", truth_check_period_s, limits::positive(), "Ground-truth contact check interval [s]");
  }
  void validate() const { validate_params(*this, "execution"); }
};

/// What happened during one move.
struct MoveReport {
  bool success = false;           ///< Camera within tolerance at the end.
  double position_error_m = 0.0;  ///< Final camera position error.
  double angle_error_rad = 0.0;   ///< Final camera rotation error.
  double duration_s = 0.0;        ///< Simulated time of the move, settling included.
  int self_contact_steps = 0;     ///< Steps with a robot-robot contact (simulator).
  int env_contact_steps = 0;      ///< Steps with a robot contact other than the ground (simulator).
  int truth_contact_checks = 0;   ///< Checked states in collision with the ground truth.
  int truth_checks = 0;           ///< Ground-truth checks made.
  std::set<std::string> contact_pairs;  ///< "robot_geom | other" for every contact seen.
  std::string message;
  int contacts() const { return self_contact_steps + env_contact_steps + truth_contact_checks; }
};

/// Runs `trajectory` from the simulator's current state: the servo set points follow the
/// trajectory's reference each step; after its end the arm may settle up to settle_time_s.
template <class Sim>
MoveReport execute_arm_move(Sim& sim, const ArmTrajectory& trajectory, const Pose& T_world_camera_goal,
                            const ExecutionParams& params, const CollisionChecker* truth = nullptr) {
  MoveReport r;
  const double t0 = sim.time();
  const double t_end = trajectory.duration();
  double next_truth_check = 0.0;
  auto within = [&] {
    pose_error(sim.camera_pose(), T_world_camera_goal, &r.position_error_m, &r.angle_error_rad);
    return r.position_error_m <= params.position_tolerance_m && r.angle_error_rad <= params.angle_tolerance_rad;
  };
  for (;;) {
    const double t = sim.time() - t0;
    if (t >= t_end && (within() || t >= t_end + params.settle_time_s)) break;
    sim.set_arm_targets(trajectory.sample(t).q);
    sim.step();
    bool self = false, env = false;
    for (const auto& c : sim.robot_contacts()) {
      if (c.self_collision) {
        self = true;
      } else if (c.other_geom != "ground") {
        env = true;
      } else {
        continue;
      }
      r.contact_pairs.insert(c.robot_geom + " | " + c.other_geom);
    }
    r.self_contact_steps += self;
    r.env_contact_steps += env;
    if (truth && sim.time() - t0 >= next_truth_check) {
      next_truth_check += params.truth_check_period_s;
      ++r.truth_checks;
      const CollisionReport cr = truth->report(sim.base_pose(), sim.arm_positions());
      if (cr.in_collision) {
        ++r.truth_contact_checks;
        r.contact_pairs.insert(cr.pairs.begin(), cr.pairs.end());
      }
    }
  }
  r.duration_s = sim.time() - t0;
  r.success = within();
  r.message = r.success ? "camera within tolerance" : "camera missed the goal by " + std::to_string(r.position_error_m) +
                                                          " m, " + std::to_string(r.angle_error_rad * 180.0 / M_PI) + " deg";
  return r;
}

}  // namespace canopy::motion
