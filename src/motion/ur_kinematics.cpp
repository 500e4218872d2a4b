#include "canopy/motion/ur_kinematics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/robot/robot_description.h"

namespace canopy::motion {

namespace {

constexpr double kDhTolerance = 1e-9;     // URDF origins must match a DH row this closely.
constexpr double kAcosSlack = 1e-10;      // Round-off allowed outside [-1, 1] at workspace borders.
constexpr double kWristSingular = 1e-12;  // |sin q5| below this: q6 is free.

// Splits a fixed transform into a DH row Tz(d) Tx(a) Rx(alpha); false if it is not one.
bool to_dh_row(const Pose& T, double* d, double* a, double* alpha) {
  const Vec3 t = T.translation();
  const Mat3 R = T.linear();
  *a = t.x();
  *d = t.z();
  *alpha = std::atan2(R(2, 1), R(1, 1));
  const Mat3 Rx = Eigen::AngleAxisd(*alpha, Vec3::UnitX()).toRotationMatrix();
  return std::abs(t.y()) < kDhTolerance && (R - Rx).norm() < kDhTolerance;
}

// Row i of the DH product as a matrix, given cos/sin of q.
inline Pose dh_row(double c, double s, double d, double a, double ca, double sa) {
  Pose A;
  A.matrix() << c, -s * ca, s * sa, a * c,  //
      s, c * ca, -c * sa, a * s,            //
      0, sa, ca, d,                         //
      0, 0, 0, 1;
  return A;
}

bool clamp_unit(double* x) {
  if (*x > 1.0 + kAcosSlack || *x < -1.0 - kAcosSlack) return false;
  *x = std::clamp(*x, -1.0, 1.0);
  return true;
}

}  // namespace

UrDh UrDh::from_description(const robot::RobotDescription& desc, const RobotConfig& config) {
  UrDh dh;
  const std::string where = "robot description '" + desc.name() + "'";
  std::string parent = config.arm_base_frame;
  for (int i = 0; i < kArmDof; ++i) {
    const robot::Joint& j = desc.joint(config.arm_joints[static_cast<size_t>(i)]);
    if (j.parent_link != parent)
      throw InputError(where + ": arm joint '" + j.name + "' is not a child of '" + parent + "'");
    if (!j.movable() || j.type == robot::JointType::kPrismatic || (j.axis - Vec3::UnitZ()).norm() > kDhTolerance)
      throw InputError(where + ": arm joint '" + j.name + "' must be revolute about its z axis (DH form)");
    if (i == 0) {
      if (!j.T_parent_joint.isApprox(Pose::Identity(), kDhTolerance))
        throw InputError(where + ": joint '" + j.name + "' origin must be the identity (arm base = DH frame 0)");
    } else {
      const size_t r = static_cast<size_t>(i - 1);
      if (!to_dh_row(j.T_parent_joint, &dh.d[r], &dh.a[r], &dh.alpha[r]))
        throw InputError(where + ": joint '" + j.name + "' origin is not a standard DH row Tz(d) Tx(a) Rx(alpha)");
    }
    parent = j.child_link;
  }
  const Pose T_last = desc.relative_pose(parent, config.tool_frame, {});
  if (!to_dh_row(T_last, &dh.d[5], &dh.a[5], &dh.alpha[5]))
    throw InputError(where + ": '" + config.tool_frame + "' in '" + parent + "' is not a standard DH row");

  // The closed-form solution relies on the UR structure: three parallel axes (2, 3, 4),
  // zero offsets elsewhere.
  const double pi2 = M_PI / 2;
  const bool ur_form = std::abs(dh.d[1]) < kDhTolerance && std::abs(dh.d[2]) < kDhTolerance &&
                       std::abs(dh.a[0]) < kDhTolerance && std::abs(dh.a[3]) < kDhTolerance &&
                       std::abs(dh.a[4]) < kDhTolerance && std::abs(dh.a[5]) < kDhTolerance &&
                       std::abs(dh.alpha[0] - pi2) < kDhTolerance && std::abs(dh.alpha[1]) < kDhTolerance &&
                       std::abs(dh.alpha[2]) < kDhTolerance && std::abs(dh.alpha[3] - pi2) < kDhTolerance &&
                       std::abs(dh.alpha[4] + pi2) < kDhTolerance && std::abs(dh.alpha[5]) < kDhTolerance &&
                       std::abs(dh.d[5]) > kDhTolerance && std::abs(dh.a[1]) > kDhTolerance &&
                       std::abs(dh.a[2]) > kDhTolerance;
  if (!ur_form) throw InputError(where + ": arm chain is not in UR standard DH form");
  return dh;
}

UrKinematics::UrKinematics(const UrDh& dh) : dh_(dh) {
  for (int i = 0; i < 6; ++i) {
    ca_[i] = std::cos(dh_.alpha[i]);
    sa_[i] = std::sin(dh_.alpha[i]);
    // Exact zeros keep the products clean (cos(pi/2) is 6e-17, not 0).
    if (std::abs(ca_[i]) < 1e-15) ca_[i] = 0.0;
    if (std::abs(sa_[i]) < 1e-15) sa_[i] = 0.0;
  }
}

Pose UrKinematics::fk(const ArmConfig& q) const {
  Pose T = dh_row(std::cos(q[0]), std::sin(q[0]), dh_.d[0], dh_.a[0], ca_[0], sa_[0]);
  for (int i = 1; i < 6; ++i) T = T * dh_row(std::cos(q[i]), std::sin(q[i]), dh_.d[i], dh_.a[i], ca_[i], sa_[i]);
  return T;
}

void UrKinematics::fk_frames(const ArmConfig& q, std::array<Pose, 6>* frames) const {
  Pose T = Pose::Identity();
  for (int i = 0; i < 6; ++i) {
    T = T * dh_row(std::cos(q[i]), std::sin(q[i]), dh_.d[i], dh_.a[i], ca_[i], sa_[i]);
    (*frames)[static_cast<size_t>(i)] = T;
  }
}

UrIkSolutions UrKinematics::ik(const Pose& T06, double q6_seed) const {
  UrIkSolutions out;
  if (!T06.matrix().allFinite() || !std::isfinite(q6_seed)) return out;
  const double d1 = dh_.d[0], d4 = dh_.d[3], d5 = dh_.d[4], d6 = dh_.d[5], a2 = dh_.a[1], a3 = dh_.a[2];
  const Mat3& R = T06.linear();
  const Vec3 x6 = R.col(0), y6 = R.col(1), z6 = R.col(2);
  const Vec3 p06 = T06.translation();
  const Vec3 p05 = p06 - d6 * z6;

  // Shoulder: the wrist centre lies d4 along z1 = (sin q1, -cos q1, 0).
  const double r = std::hypot(p05.x(), p05.y());
  if (r < std::abs(d4) * (1.0 - kAcosSlack)) return out;
  const double psi = std::atan2(p05.y(), p05.x());
  double ratio = d4 / r;
  if (!clamp_unit(&ratio)) return out;
  const double phi = std::asin(ratio);
  const double q1s[2] = {wrap_angle(psi + phi), wrap_angle(psi + M_PI - phi)};
  const double c6_seed = std::cos(q6_seed), s6_seed = std::sin(q6_seed);

  for (double q1 : q1s) {
    const double c1 = std::cos(q1), s1 = std::sin(q1);
    // z1 = (s1, -c1, 0); x1 = (c1, s1, 0); y1 = world z (frame 1 after alpha1 = pi/2).
    // Wrist 2: z6 . z1 = cos q5.
    double c5 = (p06.x() * s1 - p06.y() * c1 - d4) / d6;
    if (!clamp_unit(&c5)) continue;
    const double s5_abs = std::sqrt(std::max(0.0, 1.0 - c5 * c5));
    const double q5a = std::atan2(s5_abs, c5);
    // z1 seen from frame 6 is (s5 c6, -s5 s6, c5).
    const double wx = x6.x() * s1 - x6.y() * c1, wy = y6.x() * s1 - y6.y() * c1;
    for (int wrist = 0; wrist < 2; ++wrist) {
      const double s5 = wrist == 0 ? s5_abs : -s5_abs;
      const double q5 = wrist == 0 ? q5a : -q5a;
      double c6 = c6_seed, s6 = s6_seed, q6 = q6_seed;
      if (std::abs(s5) > kWristSingular) {
        c6 = wx / s5;
        s6 = -wy / s5;
        const double n = std::hypot(c6, s6);
        c6 /= n;
        s6 /= n;
        q6 = std::atan2(s6, c6);
      }
      // Frame 4: z4 = -y5 = -(s6 x6 + c6 y6), x4 = c5 c6 x6 - c5 s6 y6 - s5 z6, and its
      // origin p04 = p05 + d5 (s6 x6 + c6 y6). Joints 2-4 then form a planar 2R chain in
      // frame 1, with q234 the angle of x4 in that plane.
      const Vec3 y5 = s6 * x6 + c6 * y6;
      const Vec3 p04 = p05 + d5 * y5;
      const Vec3 x4 = c5 * (c6 * x6 - s6 * y6) - s5 * z6;
      const double px = p04.x() * c1 + p04.y() * s1, py = p04.z() - d1;
      const double q234 = std::atan2(x4.z(), x4.x() * c1 + x4.y() * s1);
      double c3 = (px * px + py * py - a2 * a2 - a3 * a3) / (2.0 * a2 * a3);
      if (!clamp_unit(&c3)) continue;
      const double s3_abs = std::sqrt(std::max(0.0, 1.0 - c3 * c3));
      const double q3a = std::atan2(s3_abs, c3);
      const double base_angle = std::atan2(py, px);
      for (int elbow = 0; elbow < 2; ++elbow) {
        const double s3 = elbow == 0 ? s3_abs : -s3_abs;
        const double q3 = elbow == 0 ? q3a : -q3a;
        const double q2 = base_angle - std::atan2(a3 * s3, a2 + a3 * c3);
        const double q4 = q234 - q2 - q3;
        ArmConfig& q = out.q[static_cast<size_t>(out.count++)];
        q = {q1, wrap_angle(q2), q3, wrap_angle(q4), q5, wrap_angle(q6)};
      }
    }
  }
  return out;
}

}  // namespace canopy::motion
