#include "canopy/mission/aisle_survey.h"

#include <algorithm>
#include <cmath>

#include "canopy/motion/base_follower.h"

namespace canopy::mission {

namespace {

double max_error(const ArmConfig& a, const ArmConfig& b) {
  double e = 0.0;
  for (int i = 0; i < kArmDof; ++i) e = std::max(e, std::abs(a[static_cast<size_t>(i)] - b[static_cast<size_t>(i)]));
  return e;
}

// Steps the simulation and fires the video tick whenever its period has elapsed.
class Stepper {
 public:
  Stepper(sim::Simulator& sim, const SurveyCallbacks& cb) : sim_(sim), cb_(cb), next_frame_(sim.time()) {}
  void step(int n) {
    for (int k = 0; k < n; ++k) {
      if (cb_.video_tick && cb_.video_period_s > 0.0 && sim_.time() >= next_frame_ - 1e-9) {
        cb_.video_tick(sim_.time());
        next_frame_ += cb_.video_period_s;
      }
      sim_.step();
    }
  }

 private:
  sim::Simulator& sim_;
  const SurveyCallbacks& cb_;
  double next_frame_;
};

// Steps until the arm is within tolerance of `target` and nearly still, or the timeout.
double settle_arm(sim::Simulator& sim, Stepper& stepper, const ArmConfig& target, const SurveyParams& params,
                  double* error) {
  sim.set_arm_targets(target);
  sim.set_base_velocity(0.0, 0.0);
  const double t0 = sim.time();
  while (sim.time() - t0 < params.arm_timeout_s) {
    stepper.step(10);
    const ArmConfig v = sim.arm_velocities();
    double speed = 0.0;
    for (double x : v) speed = std::max(speed, std::abs(x));
    if (max_error(sim.arm_positions(), target) < params.arm_settle_tolerance_rad && speed < 1e-2) break;
  }
  *error = max_error(sim.arm_positions(), target);
  return sim.time() - t0;
}

}  // namespace

SurveyResult run_aisle_survey(sim::Simulator& sim, sim::Renderer& renderer, const world::WorldSpec& spec,
                              const SurveyParams& params, const SurveyCallbacks& callbacks) {
  SurveyResult result;
  Stepper stepper(sim, callbacks);
  const auto& progress = callbacks.progress;
  const RobotConfig& cfg = sim.robot_config();
  // The home view looks at the left row; the same pose with the shoulder turned by pi looks
  // at the right row (mirror image through the arm's base axis).
  const ArmConfig look_left = cfg.home;
  ArmConfig look_right = cfg.home;
  look_right[0] = std::remainder(look_right[0] + M_PI, 2.0 * M_PI);
  const motion::BaseFollowerParams follower_params = motion::BaseFollowerParams::from_robot(cfg);
  const double dt = sim.timestep();

  for (int stop = 0; stop < spec.rows.plants_per_row; ++stop) {
    const BasePose goal{spec.rows.x_start_m + stop * spec.rows.plant_spacing_m + params.stop_offset_m, 0.0, 0.0};
    result.stop_goals.push_back(goal);
    if (progress) progress("stop " + std::to_string(stop + 1) + "/" + std::to_string(spec.rows.plants_per_row) +
                           ": driving to x = " + std::to_string(goal.x_m));
    motion::BaseFollower follower(follower_params, {goal});
    bool reached = false;
    const double t0 = sim.time();
    while (!reached && sim.time() - t0 < params.base_timeout_s) {
      const motion::BaseCommand cmd = follower.update(sim.base_pose(), dt);
      reached = cmd.done;
      sim.set_base_velocity(cmd.v_m_s, cmd.omega_rad_s);
      stepper.step(1);
    }
    sim.set_base_velocity(0.0, 0.0);
    const BasePose at = sim.base_pose();
    result.stop_position_error_m.push_back(std::hypot(at.x_m - goal.x_m, at.y_m - goal.y_m));
    result.all_stops_reached &= reached;
    for (int side = 0; side < spec.rows.rows; ++side) {
      SurveyObservation obs;
      obs.stop = stop;
      obs.side = side == 0 ? "left" : "right";
      obs.settle_time_s = settle_arm(sim, stepper, side == 0 ? look_left : look_right, params, &obs.arm_error_rad);
      obs.base = sim.base_pose();
      obs.frame = renderer.render_wrist_camera();
      if (progress) progress("stop " + std::to_string(stop + 1) + ": " + obs.side + " view, arm settled in " +
                             std::to_string(obs.settle_time_s) + " s");
      result.observations.push_back(std::move(obs));
    }
  }
  result.sim_time_s = sim.time();
  return result;
}

}  // namespace canopy::mission
