#pragma once
// Driving the simulated robot: a stepper that every loop steps through (video ticks, a test
// hook, divergence detection, Ctrl-C), the base drive loop and arm settling. The mission and
// any other loop on the robot share these instead of stepping MuJoCo themselves.

#include <functional>
#include <stdexcept>
#include <string>

#include "canopy/motion/base_follower.h"
#include "canopy/motion/execution.h"
#include "canopy/motion/robot_model.h"
#include "canopy/sim/simulator.h"

namespace canopy::mission {

/// Thrown by SimStepper::step when the simulation diverged (NaN, or MuJoCo's bad-state
/// warnings); the caller restores a snapshot.
struct SimulationDiverged : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// Thrown by SimStepper::step when a stop was requested (Ctrl-C).
struct StopRequested : std::runtime_error {
  StopRequested() : std::runtime_error("stop requested") {}
};

/// Steps a simulator, firing the video tick every `video_period_s` of simulated time.
class SimStepper {
 public:
  SimStepper(sim::Simulator& sim, double video_period_s, std::function<void()> video_tick,
             std::function<bool()> stop_requested = nullptr);
  /// Advances n steps; throws SimulationDiverged or StopRequested.
  void step(int n = 1);
  /// Called before every step (fault injection in tests); null for none.
  void set_before_step(std::function<void()> hook) { before_step_ = std::move(hook); }
  sim::Simulator& sim() { return sim_; }

 private:
  sim::Simulator& sim_;
  double period_;
  std::function<void()> tick_;
  std::function<bool()> stop_;
  std::function<void()> before_step_;
  double next_frame_;
  long steps_ = 0;
};

/// The simulator as motion::execute_arm_move sees it, stepping through a SimStepper. The
/// camera pose is the robot model's forward kinematics of the current joints (exactly what
/// MuJoCo's camera is, without another MuJoCo kinematics pass per step).
template <class Model>
class SteppedSim {
 public:
  SteppedSim(SimStepper& stepper, const Model& model) : stepper_(stepper), model_(model) {}
  void set_arm_targets(const ArmConfig& q) { stepper_.sim().set_arm_targets(q); }
  void step() { stepper_.step(1); }
  double time() const { return stepper_.sim().time(); }
  Pose camera_pose() const { return model_.camera_pose(base_pose(), arm_positions()); }
  BasePose base_pose() const { return stepper_.sim().base_pose(); }
  ArmConfig arm_positions() const { return stepper_.sim().arm_positions(); }
  std::vector<sim::RobotContact> robot_contacts() const { return stepper_.sim().robot_contacts(); }

 private:
  SimStepper& stepper_;
  const Model& model_;
};

/// Outcome of driving to a base pose.
struct DriveReport {
  bool reached = false;
  double duration_s = 0.0;
  double position_error_m = 0.0;
  int checks = 0;             ///< Base checks made (every check_period_s).
  int contacts = 0;           ///< Checks that found the base touching something.
};

/// Drives the base to `goal` with the waypoint follower, up to `timeout_s` of simulated time.
/// `base_in_contact` (may be null) is asked every `check_period_s` whether the base touches
/// anything (e.g. the true plants).
DriveReport drive_base(SimStepper& stepper, const motion::BaseFollowerParams& params, const BasePose& goal,
                       double timeout_s, const std::function<bool(const BasePose&)>& base_in_contact,
                       double check_period_s);

/// Outcome of an arm move on the simulator.
struct ArmMove {
  motion::MoveReport report;
  std::string diverged;  ///< What diverged ("" = nothing; the simulator is back at `before`).
  double time_s = 0.0;   ///< Simulated time the move took (0 when it diverged).
};

/// Executes `trajectory` on the stepper's simulator (motion::execute_arm_move, arm-plant
/// contacts counted against `truth`); a divergence restores `before`, the state the move
/// started from.
ArmMove move_arm(SimStepper& stepper, const motion::RobotModel& model, const motion::ArmTrajectory& trajectory,
                 const Pose& T_world_camera_goal, const motion::ExecutionParams& params,
                 const motion::CollisionChecker* truth, const sim::SimState& before);

}  // namespace canopy::mission
