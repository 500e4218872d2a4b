#include "canopy/motion/workspace_filter.h"


#include <algorithm>
#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/motion/collision.h"

namespace canopy::motion {

namespace {

// Positions along a view whose distances are kept for the bounds (the default settings try 41).
constexpr std::size_t kMaxShifts = 128;

enum class Membership { kIn, kOut, kUnknown };

// Whether the position t along the viewing line lies within `radius` of the workspace, from
// the distances d[i] measured at positions ts[i] on the same line (unit direction): kIn or kOut
// when the triangle inequality decides it by more than kBoundMargin_m (far above the rounding
// of the distances, about 1e-16 m), else kUnknown (measure it).
constexpr double kBoundMargin_m = 1e-9;
Membership bounded_membership(const double* ts, const double* d, std::size_t n, double t, double radius) {
  for (std::size_t i = 0; i < n; ++i) {
    const double gap = std::abs(t - ts[i]);
    if (d[i] - gap > radius + kBoundMargin_m) return Membership::kOut;
    if (d[i] + gap < radius - kBoundMargin_m) return Membership::kIn;
  }
  return Membership::kUnknown;
}

}  // namespace

const char* to_string(ViewVerdict v) {
  switch (v) {
    case ViewVerdict::kKept: return "kept";
    case ViewVerdict::kOutsideWorkspace: return "outside_workspace";
    case ViewVerdict::kNoIk: return "no_ik";
    case ViewVerdict::kInCollision: return "in_collision";
    case ViewVerdict::kInvalidInput: return "invalid_input";
  }
  return "unknown";
}

WorkspaceFilter::~WorkspaceFilter() = default;
WorkspaceFilter::WorkspaceFilter(WorkspaceFilter&&) noexcept = default;

WorkspaceFilter::WorkspaceFilter(const RobotModel& model, const WorkspaceParams& params)
    : model_(&model), params_(params) {
  params_.validate();
  // Joint combinations drawn uniformly within one turn of each joint (wider ranges only
  // repeat positions) and the planning limits.
  Rng rng(params_.seed);
  const ArmLimits& lim = model.limits();
  ArmConfig lo{}, hi{};
  for (int i = 0; i < kArmDof; ++i) {
    lo[static_cast<size_t>(i)] = std::max(lim.lower[i], -M_PI);
    hi[static_cast<size_t>(i)] = std::min(lim.upper[i], M_PI);
  }
  const double arm_height = model.T_base_arm().translation().z();
  std::vector<Vec3> points;
  points.reserve(static_cast<size_t>(params_.samples));
  for (int s = 0; s < params_.samples; ++s) {
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = rng.uniform(lo[static_cast<size_t>(i)], hi[static_cast<size_t>(i)]);
    const Vec3 p = model.camera_in_arm(q).translation();
    // The base is planar, so height above the ground is the same in every base pose.
    if (p.z() + arm_height < params_.min_camera_height_m) continue;
    points.push_back(p);
  }
  CANOPY_CHECK(!points.empty(), "workspace filter: no sample above the ground");
  tree_ = std::make_unique<PointKdTree>(std::move(points), 16);
}

double WorkspaceFilter::distance_to_workspace(const BasePose& base, const Vec3& p_world) const {
  if (!p_world.allFinite() || !std::isfinite(base.x_m) || !std::isfinite(base.y_m) || !std::isfinite(base.yaw_rad))
    return std::numeric_limits<double>::infinity();
  const Pose T_arm_world = (RobotModel::T_world_base(base) * model_->T_base_arm()).inverse(Eigen::Isometry);
  const Vec3 p = T_arm_world * p_world;
  std::size_t index = 0;
  double d2 = 0.0;
  tree_->nearest(p, &index, &d2);
  return std::sqrt(d2);
}

FilteredView WorkspaceFilter::filter(const BasePose& base, const Pose& T_world_camera, const ArmConfig& seed,
                                     const CollisionChecker* checker) const {
  FilteredView out;
  bool seed_ok = true;
  for (double v : seed) seed_ok = seed_ok && std::isfinite(v);
  if (!T_world_camera.matrix().allFinite() || !seed_ok || !std::isfinite(base.x_m) || !std::isfinite(base.y_m) ||
      !std::isfinite(base.yaw_rad))
    return out;  // kInvalidInput

  // Shifts along the viewing direction, smallest first (forward first on ties).
  std::vector<double> shifts = {0.0};
  const double step = params_.shift_step_m;
  const int n_fwd = static_cast<int>(std::floor(params_.max_forward_shift_m / step + 1e-9));
  const int n_back = static_cast<int>(std::floor(params_.max_backward_shift_m / step + 1e-9));
  for (int k = 1; k <= std::max(n_fwd, n_back); ++k) {
    if (k <= n_fwd) shifts.push_back(k * step);
    if (k <= n_back) shifts.push_back(-k * step);
  }
  const Vec3 p0 = T_world_camera.translation();
  const Vec3 dir = T_world_camera.linear().col(2);
  bool any_workspace = false, any_ik = false;
  // Membership of most positions follows from the distances already measured along the line
  // (triangle inequality: a position |t - t'| from one at distance d' is within d' +- |t - t'|
  // of the workspace), so their nearest-neighbour query is skipped: the same verdicts, fewer
  // queries (the filter's largest cost at planning, issue 47).
  double measured_t[kMaxShifts], measured_d[kMaxShifts];
  std::size_t measured = 0;
  const double radius = params_.membership_radius_m;
  for (double t : shifts) {
    Pose T = T_world_camera;
    T.translation() = p0 + t * dir;
    const Membership m = bounded_membership(measured_t, measured_d, measured, t, radius);
    if (m == Membership::kOut) continue;
    if (m == Membership::kUnknown) {
      const double d = distance_to_workspace(base, T.translation());
      if (measured < kMaxShifts) {
        measured_t[measured] = t;
        measured_d[measured] = d;
        ++measured;
      }
      if (!(d <= radius)) continue;
    }
    any_workspace = true;
    const IkResult ik = model_->camera_ik(base, T, seed);
    if (ik.empty()) continue;
    any_ik = true;
    for (int s = 0; s < ik.count; ++s) {
      const ArmConfig& q = ik.q[static_cast<size_t>(s)];
      if (checker && checker->in_collision(base, q)) continue;
      out.verdict = ViewVerdict::kKept;
      out.T_world_camera = T;
      out.shift_m = t;
      out.q = q;
      return out;
    }
  }
  out.verdict = !any_workspace ? ViewVerdict::kOutsideWorkspace : !any_ik ? ViewVerdict::kNoIk : ViewVerdict::kInCollision;
  return out;
}

}  // namespace canopy::motion
