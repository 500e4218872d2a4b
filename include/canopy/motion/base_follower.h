#pragma once
// Waypoint follower for the planar, differential-drive base (Husky-like): drives through a
// list of base poses and stops at the last one within 2 cm and 1 degree. Commands are a
// forward speed along the heading and a yaw rate, both kept within speed and acceleration
// limits. MuJoCo-free: the simulator turns the command into base velocity servo targets.

#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/common/types.h"

namespace canopy {
struct RobotConfig;
class YamlReader;
}  // namespace canopy

namespace canopy::motion {

/// Limits, tolerances and gains of the base follower. Defaults: Husky A200 (docs/background/robot_and_camera.md).
struct BaseFollowerParams {
  double max_speed_m_s = 1.0;
  double max_yaw_rate_rad_s = 2.0;
  double max_accel_m_s2 = 1.0;
  double max_yaw_accel_rad_s2 = 2.0;
  double position_tolerance_m = 0.02;            ///< Final position tolerance.
  double yaw_tolerance_rad = 0.017453292519943295;  ///< Final heading tolerance (1 deg).
  /// The follower aims at this fraction of the tolerances so that small drift after
  /// stopping stays inside them (hysteresis between "arrived" and "must correct").
  double settle_fraction = 0.5;
  /// Intermediate waypoints count as passed within this distance.
  double waypoint_radius_m = 0.10;
  /// Proportional gains: heading error -> yaw rate, distance -> speed.
  double heading_gain_per_s = 3.0;
  double distance_gain_per_s = 1.5;
  /// Braking profiles use this fraction of the acceleration limits, leaving margin for the
  /// discrete-time rate limiter (braking late would overshoot).
  double braking_fraction = 0.8;
  /// Above this heading error the base turns in place before driving.
  double turn_in_place_rad = 0.6;
  /// Targets behind the base closer than this are approached in reverse.
  double reverse_max_distance_m = 0.5;
  /// The base counts as stopped when its measured speeds are below these.
  double stopped_speed_m_s = 0.005;
  double stopped_yaw_rate_rad_s = 0.01;

  /// Limits from robot.yaml, the rest at defaults.
  static BaseFollowerParams from_robot(const RobotConfig& robot);

  template <class A>
  void visit(A& a) {
    a("max_speed_m_s", max_speed_m_s, limits::positive(), "Forward speed limit (robot.yaml) [m/s]");
    a("max_yaw_rate_rad_s", max_yaw_rate_rad_s, limits::positive(), "Yaw rate limit (robot.yaml) [rad/s]");
    a("max_accel_m_s2", max_accel_m_s2, limits::positive(), "Acceleration limit (robot.yaml) [m/s^2]");
    a("max_yaw_accel_rad_s2", max_yaw_accel_rad_s2, limits::positive(), "Yaw acceleration limit (robot.yaml) [rad/s^2]");
    a("position_tolerance_m", position_tolerance_m, limits::positive(), "Final position tolerance [m]");
    a("yaw_tolerance_rad", yaw_tolerance_rad, limits::positive(), "Final heading tolerance [rad]");
    a("settle_fraction", settle_fraction, limits::open(0.0, 1.0), "The follower aims at this fraction of the tolerances");
    a("waypoint_radius_m", waypoint_radius_m, limits::positive(), "Intermediate waypoints count as passed this close [m]");
    a("heading_gain_per_s", heading_gain_per_s, limits::positive(), "Heading error -> yaw rate gain [1/s]");
    a("distance_gain_per_s", distance_gain_per_s, limits::positive(), "Distance -> speed gain [1/s]");
    a("braking_fraction", braking_fraction, limits::above_up_to(0.0, 1.0), "Braking uses this fraction of the limits");
    a("turn_in_place_rad", turn_in_place_rad, limits::positive(), "Above this heading error the base turns in place [rad]");
    a("reverse_max_distance_m", reverse_max_distance_m, limits::non_negative(),
      "Targets behind the base closer than this are approached in reverse [m]");
    a("stopped_speed_m_s", stopped_speed_m_s, limits::positive(), "Stopped below this speed [m/s]");
    a("stopped_yaw_rate_rad_s", stopped_yaw_rate_rad_s, limits::positive(), "... and this yaw rate [rad/s]");
  }
  /// Throws InputError naming the first invalid field.
  void validate() const { validate_params(*this, "base follower"); }
};

/// One control command for the base: forward speed and yaw rate.
struct BaseCommand {
  double v_m_s = 0;
  double omega_rad_s = 0;
  bool done = false;   ///< Final pose reached within tolerance and the base stopped.
  std::string fault;   ///< Non-empty on bad input to update() (the command is then a stop).
};

/// Follows waypoints with a differential-drive base. Not thread-safe (keeps the last
/// command for the acceleration limits).
class BaseFollower {
 public:
  /// The last waypoint's yaw is the final heading; the others' yaws are ignored. Throws
  /// InputError on an empty list, non-finite poses or invalid parameters.
  BaseFollower(const BaseFollowerParams& params, std::vector<BasePose> waypoints);

  /// Next command given the measured pose, dt_s after the previous call.
  BaseCommand update(const BasePose& current, double dt_s);

  /// Index of the waypoint currently driven to.
  size_t target_index() const { return target_; }
  const BaseFollowerParams& params() const { return params_; }
  const std::vector<BasePose>& waypoints() const { return waypoints_; }

 private:
  enum class Phase { kDrive, kAlign };
  BaseCommand limited(double v_des, double omega_des, double dt_s);
  double corner_speed(size_t i, const BasePose& current) const;

  BaseFollowerParams params_;
  std::vector<BasePose> waypoints_;
  size_t target_ = 0;
  Phase phase_ = Phase::kDrive;
  double v_ = 0.0, omega_ = 0.0;
  bool have_last_ = false;
  BasePose last_pose_;
};

}  // namespace canopy::motion
