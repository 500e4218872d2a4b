#pragma once
// Closed-form kinematics of a UR-type arm in standard DH form (UR3 by default): forward
// kinematics from DH frame 0 to DH frame 6 and the analytic inverse (Hawkins, "Analytic
// inverse kinematics for the Universal Robots UR-5/UR-10 arms", 2013) returning up to 8
// solutions. The DH parameters are read from the robot description, whose UR joint origins
// are the DH rows, so there is one source of kinematics.

#include <array>

#include "canopy/robot/robot_config.h"
#include "canopy/common/types.h"

namespace canopy::robot {
class RobotDescription;
}

namespace canopy::motion {

/// Standard DH parameters of a UR arm: A_i = Rz(q_i) Tz(d_i) Tx(a_i) Rx(alpha_i).
struct UrDh {
  std::array<double, 6> d = {0.1519, 0, 0, 0.11235, 0.08535, 0.0819};
  std::array<double, 6> a = {0, -0.24365, -0.21325, 0, 0, 0};
  std::array<double, 6> alpha = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};

  /// Reads the DH rows from the URDF joint origins along `arm_joints` from `base_frame`
  /// (DH frame 0) to `tool_frame` (DH frame 6). Throws InputError when the chain is not in
  /// UR standard DH form (the closed-form IK would then be wrong).
  static UrDh from_description(const robot::RobotDescription& description, const RobotConfig& config);
};

/// Up to 8 raw IK solutions, each joint in (-pi, pi].
struct UrIkSolutions {
  std::array<ArmConfig, 8> q;
  int count = 0;
};

/// Closed-form forward and inverse kinematics of DH frame 6 in DH frame 0. Stateless and
/// thread-safe.
class UrKinematics {
 public:
  explicit UrKinematics(const UrDh& dh = UrDh{});

  /// Pose of DH frame 6 in DH frame 0.
  Pose fk(const ArmConfig& q) const;
  /// Poses of DH frames 1..6 in frame 0 (frames[i] is frame i+1).
  void fk_frames(const ArmConfig& q, std::array<Pose, 6>* frames) const;

  /// All analytic solutions for T_0_6 (no limit filtering). `q6_seed` is used for the wrist
  /// singularity (sin q5 ~ 0), where q6 is free. Non-finite input gives no solutions.
  UrIkSolutions ik(const Pose& T_0_6, double q6_seed = 0.0) const;

  const UrDh& dh() const { return dh_; }

 private:
  UrDh dh_;
  // Precomputed per-row constants.
  std::array<double, 6> ca_, sa_;
};

}  // namespace canopy::motion
