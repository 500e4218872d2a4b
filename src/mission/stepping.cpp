#include "canopy/mission/stepping.h"

#include <cmath>

namespace canopy::mission {

SimStepper::SimStepper(sim::Simulator& sim, double video_period_s, std::function<void()> video_tick,
                       std::function<bool()> stop_requested)
    : sim_(sim), period_(video_period_s), tick_(std::move(video_tick)), stop_(std::move(stop_requested)),
      next_frame_(sim.time()) {}

void SimStepper::step(int n) {
  for (int k = 0; k < n; ++k) {
    // Ctrl-C is polled every 50 steps (0.1 s simulated): cheap, and prompt enough.
    if (stop_ && steps_ % 50 == 0 && stop_()) throw StopRequested();
    if (tick_ && period_ > 0.0 && sim_.time() >= next_frame_ - 1e-9) {
      tick_();
      next_frame_ += period_;
    }
    if (before_step_) before_step_();
    sim_.step();
    ++steps_;
    if (!sim_.state_ok()) throw SimulationDiverged("the simulation diverged at t = " + std::to_string(sim_.time()) + " s");
  }
}

DriveReport drive_base(SimStepper& stepper, const motion::BaseFollowerParams& params, const BasePose& goal,
                       double timeout_s, const std::function<bool(const BasePose&)>& base_in_contact,
                       double check_period_s) {
  sim::Simulator& sim = stepper.sim();
  DriveReport r;
  motion::BaseFollower follower(params, {goal});
  const double t0 = sim.time(), dt = sim.timestep();
  double next_check = t0;
  while (!r.reached && sim.time() - t0 < timeout_s) {
    const motion::BaseCommand cmd = follower.update(sim.base_pose(), dt);
    r.reached = cmd.done;
    sim.set_base_velocity(cmd.v_m_s, cmd.omega_rad_s);
    stepper.step(1);
    if (base_in_contact && sim.time() >= next_check) {
      next_check += check_period_s;
      ++r.checks;
      r.contacts += base_in_contact(sim.base_pose());
    }
  }
  sim.set_base_velocity(0.0, 0.0);
  const BasePose at = sim.base_pose();
  r.position_error_m = std::hypot(at.x_m - goal.x_m, at.y_m - goal.y_m);
  r.duration_s = sim.time() - t0;
  return r;
}

ArmMove move_arm(SimStepper& stepper, const motion::RobotModel& model, const motion::ArmTrajectory& trajectory,
                 const Pose& T_world_camera_goal, const motion::ExecutionParams& params,
                 const motion::CollisionChecker* truth, const sim::SimState& before) {
  sim::Simulator& sim = stepper.sim();
  ArmMove m;
  SteppedSim<motion::RobotModel> stepped(stepper, model);
  const double t0 = sim.time();
  try {
    m.report = motion::execute_arm_move(stepped, trajectory, T_world_camera_goal, params, truth);
  } catch (const SimulationDiverged& e) {
    sim.restore(before);
    m.diverged = e.what();
  }
  m.time_s = sim.time() - t0;
  return m;
}

}  // namespace canopy::mission
