#include "canopy/motion/base_follower.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {

namespace {

bool finite_pose(const BasePose& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad);
}

double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }

}  // namespace

BaseFollowerParams BaseFollowerParams::from_robot(const RobotConfig& robot) {
  BaseFollowerParams p;
  p.max_speed_m_s = robot.base_max_speed_m_s;
  p.max_yaw_rate_rad_s = robot.base_max_yaw_rate_rad_s;
  p.max_accel_m_s2 = robot.base_max_accel_m_s2;
  p.max_yaw_accel_rad_s2 = robot.base_max_yaw_accel_rad_s2;
  return p;
}

BaseFollower::BaseFollower(const BaseFollowerParams& params, std::vector<BasePose> waypoints)
    : params_(params), waypoints_(std::move(waypoints)) {
  params_.validate();
  if (waypoints_.empty()) throw InputError("base follower: no waypoints given");
  for (size_t i = 0; i < waypoints_.size(); ++i) {
    if (!finite_pose(waypoints_[i]))
      throw InputError("base follower: waypoint " + std::to_string(i) + " is not finite");
  }
}

BaseCommand BaseFollower::limited(double v_des, double omega_des, double dt_s) {
  const double dv = params_.max_accel_m_s2 * dt_s;
  const double dw = params_.max_yaw_accel_rad_s2 * dt_s;
  v_ = std::clamp(v_ + std::clamp(v_des - v_, -dv, dv), -params_.max_speed_m_s, params_.max_speed_m_s);
  omega_ = std::clamp(omega_ + std::clamp(omega_des - omega_, -dw, dw), -params_.max_yaw_rate_rad_s,
                      params_.max_yaw_rate_rad_s);
  BaseCommand c;
  c.v_m_s = v_;
  c.omega_rad_s = omega_;
  return c;
}

// Speed allowed when passing intermediate waypoint i: full speed on a straight line, zero
// for a turn of 90 degrees or more (the base then turns in place there).
double BaseFollower::corner_speed(size_t i, const BasePose& current) const {
  if (i + 1 >= waypoints_.size()) return 0.0;
  const BasePose& a = i == 0 ? current : waypoints_[i - 1];
  const BasePose& b = waypoints_[i];
  const BasePose& c = waypoints_[i + 1];
  const double h1 = std::atan2(b.y_m - a.y_m, b.x_m - a.x_m);
  const double h2 = std::atan2(c.y_m - b.y_m, c.x_m - b.x_m);
  return params_.max_speed_m_s * std::max(0.0, std::cos(wrap_angle(h2 - h1)));
}

BaseCommand BaseFollower::update(const BasePose& current, double dt_s) {
  if (!finite_pose(current) || !std::isfinite(dt_s) || dt_s <= 0.0) {
    // A safety stop: the input cannot be trusted, so no acceleration limit can be honoured.
    v_ = omega_ = 0.0;
    have_last_ = false;
    BaseCommand c;
    c.fault = !finite_pose(current) ? "base follower: current pose is not finite"
                                    : "base follower: dt_s = " + std::to_string(dt_s) + " must be > 0";
    return c;
  }
  bool stopped = false;
  if (have_last_) {
    const double speed = std::hypot(current.x_m - last_pose_.x_m, current.y_m - last_pose_.y_m) / dt_s;
    const double yaw_rate = std::abs(wrap_angle(current.yaw_rad - last_pose_.yaw_rad)) / dt_s;
    stopped = speed <= params_.stopped_speed_m_s && yaw_rate <= params_.stopped_yaw_rate_rad_s;
  }
  last_pose_ = current;
  have_last_ = true;

  auto distance_to = [&](size_t i) {
    return std::hypot(waypoints_[i].x_m - current.x_m, waypoints_[i].y_m - current.y_m);
  };
  const size_t last = waypoints_.size() - 1;
  while (target_ < last && distance_to(target_) < params_.waypoint_radius_m) ++target_;
  const BasePose& goal = waypoints_[target_];
  const bool final_target = target_ == last;
  const double d = distance_to(target_);

  const double a_brake = params_.braking_fraction * params_.max_accel_m_s2;
  const double alpha_brake = params_.braking_fraction * params_.max_yaw_accel_rad_s2;
  // Yaw rate towards a heading error e: proportional near zero, braking-limited further out.
  auto yaw_rate_for = [&](double e) {
    const double mag = std::min({params_.max_yaw_rate_rad_s, std::sqrt(2.0 * alpha_brake * std::abs(e)),
                                 params_.heading_gain_per_s * std::abs(e)});
    return sign(e) * mag;
  };

  if (final_target) {
    if (phase_ == Phase::kAlign && d > params_.position_tolerance_m) phase_ = Phase::kDrive;
    if (phase_ == Phase::kDrive && d <= params_.settle_fraction * params_.position_tolerance_m)
      phase_ = Phase::kAlign;
  } else {
    phase_ = Phase::kDrive;
  }

  if (phase_ == Phase::kAlign) {
    const double e = wrap_angle(goal.yaw_rad - current.yaw_rad);
    const double omega_des = std::abs(e) <= params_.settle_fraction * params_.yaw_tolerance_rad ? 0.0 : yaw_rate_for(e);
    BaseCommand c = limited(0.0, omega_des, dt_s);
    c.done = std::abs(e) <= params_.yaw_tolerance_rad && d <= params_.position_tolerance_m && c.v_m_s == 0.0 &&
             c.omega_rad_s == 0.0 && stopped;
    return c;
  }

  // Drive towards the target position, in reverse when it is close behind.
  double e = wrap_angle(std::atan2(goal.y_m - current.y_m, goal.x_m - current.x_m) - current.yaw_rad);
  double direction = 1.0;
  if (std::abs(e) > M_PI / 2 && d < params_.reverse_max_distance_m) {
    direction = -1.0;
    e = wrap_angle(e + M_PI);
  }
  const double v_pass = final_target ? 0.0 : corner_speed(target_, current);
  double speed = std::min(params_.max_speed_m_s, std::sqrt(v_pass * v_pass + 2.0 * a_brake * d));
  if (final_target) speed = std::min(speed, params_.distance_gain_per_s * d);
  speed *= std::max(0.0, 1.0 - std::abs(e) / params_.turn_in_place_rad);
  return limited(direction * speed, yaw_rate_for(e), dt_s);
}

}  // namespace canopy::motion
