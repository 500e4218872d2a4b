#pragma once
// Time parameterisation of joint-space paths and the reference generator that the
// simulator's position actuators track. MuJoCo-free: sim/ samples the reference each step.
//
// Each straight joint-space segment of a planned path gets a synchronised trapezoidal
// velocity profile (all joints start and stop together, each within its velocity and
// acceleration limit), and the arm stops at every waypoint. The arm therefore moves exactly
// along the straight segments that the planner collision-checked; simplified paths have few
// waypoints, so the stops cost little.

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/types.h"

namespace canopy {
class YamlReader;
}

namespace canopy::motion {

struct ArmLimits;

/// Scales applied to the robot's joint limits when timing a path.
struct TrajectoryParams {
  double velocity_scale = 1.0;      ///< Fraction of robot.yaml's max joint velocities.
  double acceleration_scale = 1.0;  ///< Fraction of robot.yaml's max joint accelerations.

  template <class A>
  void visit(A& a) {
    a("velocity_scale", velocity_scale, limits::above_up_to(0.0, 1.0), "Fraction of robot.yaml's max joint velocities");
    a("acceleration_scale", acceleration_scale, limits::above_up_to(0.0, 1.0),
      "Fraction of robot.yaml's max joint accelerations");
  }
  void validate() const { validate_params(*this, "trajectory"); }
};

/// Position, velocity and acceleration of the arm at one instant.
struct ArmReference {
  ArmConfig q{}, qd{}, qdd{};
  bool finished = false;  ///< The trajectory has ended (q is the final waypoint).
};

/// A timed joint-space trajectory through waypoints.
class ArmTrajectory {
 public:
  ArmTrajectory() = default;
  /// Times `path` (at least one waypoint) within `max_velocity`, `max_acceleration`
  /// (per joint, > 0). Throws InputError on non-finite waypoints or limits.
  static ArmTrajectory time_parameterize(const std::vector<ArmConfig>& path, const ArmConfig& max_velocity,
                                         const ArmConfig& max_acceleration);
  /// Same with the limits of a robot model scaled by `params`.
  static ArmTrajectory time_parameterize(const std::vector<ArmConfig>& path, const ArmLimits& limits,
                                         const TrajectoryParams& params);

  bool empty() const { return waypoints_.empty(); }
  double duration() const { return times_.empty() ? 0.0 : times_.back(); }
  const std::vector<ArmConfig>& waypoints() const { return waypoints_; }
  /// Arrival time at each waypoint (the first is 0).
  const std::vector<double>& times() const { return times_; }
  /// State at time t (clamped to [0, duration]).
  ArmReference sample(double t) const;

 private:
  struct Segment {
    double t0 = 0, T = 0, t_acc = 0, s_dot = 0, s_ddot = 0;  // s in [0, 1] along the segment
  };
  std::vector<ArmConfig> waypoints_;
  std::vector<double> times_;
  std::vector<Segment> segments_;
};

/// The reference the simulator tracks: a trajectory plus a settling window after its end.
class TrajectoryTracker {
 public:
  /// `settle_time_s`: how long after the trajectory's end the controller may settle before
  /// the move counts as finished.
  explicit TrajectoryTracker(ArmTrajectory trajectory, double settle_time_s = 0.5);

  /// Reference at `t_s` seconds after the start of the move.
  ArmReference reference(double t_s) const { return trajectory_.sample(t_s); }
  /// Time after which the move is over (trajectory plus settling).
  double end_time_s() const { return trajectory_.duration() + settle_time_s_; }
  const ArmTrajectory& trajectory() const { return trajectory_; }

 private:
  ArmTrajectory trajectory_;
  double settle_time_s_;
};

/// True if `actual` is within `tolerance_m` and `tolerance_rad` of `goal` (position
/// distance and rotation angle). The move criterion is 1 cm and 2 degrees.
bool pose_within(const Pose& actual, const Pose& goal, double tolerance_m, double tolerance_rad);
/// Position distance and rotation angle between two poses.
void pose_error(const Pose& actual, const Pose& goal, double* position_m, double* angle_rad);

}  // namespace canopy::motion
