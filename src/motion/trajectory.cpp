#include "canopy/motion/trajectory.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/motion/robot_model.h"

namespace canopy::motion {

ArmTrajectory ArmTrajectory::time_parameterize(const std::vector<ArmConfig>& path, const ArmLimits& limits,
                                               const TrajectoryParams& params) {
  params.validate();
  ArmConfig v = limits.max_velocity, a = limits.max_acceleration;
  for (int i = 0; i < kArmDof; ++i) {
    v[i] *= params.velocity_scale;
    a[i] *= params.acceleration_scale;
  }
  return time_parameterize(path, v, a);
}

ArmTrajectory ArmTrajectory::time_parameterize(const std::vector<ArmConfig>& path, const ArmConfig& vmax,
                                               const ArmConfig& amax) {
  if (path.empty()) throw InputError("trajectory: empty path");
  for (int i = 0; i < kArmDof; ++i) {
    if (!(std::isfinite(vmax[i]) && vmax[i] > 0.0 && std::isfinite(amax[i]) && amax[i] > 0.0))
      throw InputError("trajectory: joint " + std::to_string(i) + " limits must be finite and > 0");
  }
  for (size_t k = 0; k < path.size(); ++k)
    for (double x : path[k])
      if (!std::isfinite(x)) throw InputError("trajectory: waypoint " + std::to_string(k) + " is not finite");

  ArmTrajectory traj;
  traj.waypoints_.push_back(path.front());
  traj.times_.push_back(0.0);
  for (size_t k = 1; k < path.size(); ++k) {
    // Path parameter s in [0, 1]: q = q_a + s * delta. Joint limits bound s' and s''.
    double V = 1e300, A = 1e300, moved = 0.0;
    for (int i = 0; i < kArmDof; ++i) {
      const double d = std::abs(path[k][i] - path[k - 1][i]);
      moved = std::max(moved, d);
      if (d > 0.0) {
        V = std::min(V, vmax[i] / d);
        A = std::min(A, amax[i] / d);
      }
    }
    if (moved < 1e-12) continue;  // Repeated waypoint.
    Segment seg;
    seg.t0 = traj.times_.back();
    seg.s_ddot = A;
    if (V * V / A >= 1.0) {  // Triangular: the peak speed is never reached.
      seg.t_acc = std::sqrt(1.0 / A);
      seg.s_dot = A * seg.t_acc;
      seg.T = 2.0 * seg.t_acc;
    } else {
      seg.t_acc = V / A;
      seg.s_dot = V;
      seg.T = 2.0 * seg.t_acc + (1.0 - V * seg.t_acc) / V;
    }
    traj.segments_.push_back(seg);
    traj.waypoints_.push_back(path[k]);
    traj.times_.push_back(seg.t0 + seg.T);
  }
  return traj;
}

ArmReference ArmTrajectory::sample(double t) const {
  ArmReference r;
  if (waypoints_.empty()) {
    r.finished = true;
    return r;
  }
  if (std::isnan(t)) t = 0.0;  // A caller bug; holding the start is the safe answer.
  if (segments_.empty() || t >= duration()) {
    r.q = waypoints_.back();
    r.finished = true;
    return r;
  }
  t = std::max(t, 0.0);
  const size_t k = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
  const Segment& seg = segments_[std::min(k, segments_.size() - 1)];
  const double u = std::clamp(t - seg.t0, 0.0, seg.T);
  double s, sd, sdd;
  if (u < seg.t_acc) {
    s = 0.5 * seg.s_ddot * u * u;
    sd = seg.s_ddot * u;
    sdd = seg.s_ddot;
  } else if (u <= seg.T - seg.t_acc) {
    s = 0.5 * seg.s_ddot * seg.t_acc * seg.t_acc + seg.s_dot * (u - seg.t_acc);
    sd = seg.s_dot;
    sdd = 0.0;
  } else {
    const double w = seg.T - u;
    s = 1.0 - 0.5 * seg.s_ddot * w * w;
    sd = seg.s_ddot * w;
    sdd = -seg.s_ddot;
  }
  const size_t seg_index = std::min(k, segments_.size() - 1);
  const ArmConfig& qa = waypoints_[seg_index];
  const ArmConfig& qb = waypoints_[seg_index + 1];
  for (int i = 0; i < kArmDof; ++i) {
    const double d = qb[i] - qa[i];
    r.q[i] = qa[i] + s * d;
    r.qd[i] = sd * d;
    r.qdd[i] = sdd * d;
  }
  return r;
}

TrajectoryTracker::TrajectoryTracker(ArmTrajectory trajectory, double settle_time_s)
    : trajectory_(std::move(trajectory)), settle_time_s_(settle_time_s) {
  if (!(std::isfinite(settle_time_s) && settle_time_s >= 0.0))
    throw InputError("trajectory tracker: settle_time_s must be >= 0");
}

void pose_error(const Pose& actual, const Pose& goal, double* position_m, double* angle_rad) {
  *position_m = (actual.translation() - goal.translation()).norm();
  *angle_rad = Eigen::AngleAxisd(actual.linear().transpose() * goal.linear()).angle();
}

bool pose_within(const Pose& actual, const Pose& goal, double tolerance_m, double tolerance_rad) {
  double p, a;
  pose_error(actual, goal, &p, &a);
  return p <= tolerance_m && a <= tolerance_rad;
}

}  // namespace canopy::motion
