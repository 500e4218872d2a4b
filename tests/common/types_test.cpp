// The common types (common/types.h, error.h): wrap_angle against its definition (the result in
// (-pi, pi], a whole number of turns away from its argument), joint_distance as a metric
// (a 3-4-5 case, symmetry, the triangle inequality), make_pose, and CANOPY_CHECK's message.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "canopy/common/error.h"
#include "canopy/common/types.h"

namespace canopy {
namespace {

TEST(Types, WrapAngleIsInTheHalfOpenCircleAndWholeTurnsAway) {
  EXPECT_EQ(wrap_angle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_angle(M_PI), M_PI);    // pi stays
  EXPECT_DOUBLE_EQ(wrap_angle(-M_PI), M_PI);   // -pi is pi
  EXPECT_NEAR(wrap_angle(2.0 * M_PI + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(wrap_angle(-2.0 * M_PI - 0.25), -0.25, 1e-12);
  EXPECT_NEAR(wrap_angle(1.5 * M_PI), -0.5 * M_PI, 1e-12);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  for (int i = 0; i < 1000; ++i) {
    const double a = u(rng);
    const double w = wrap_angle(a);
    EXPECT_GT(w, -M_PI);
    EXPECT_LE(w, M_PI);
    const double turns = (a - w) / (2.0 * M_PI);
    EXPECT_NEAR(turns, std::round(turns), 1e-9) << a;
    EXPECT_NEAR(wrap_angle(w), w, 1e-15);  // idempotent
  }
}

TEST(Types, JointDistanceIsAMetric) {
  const ArmConfig zero{};
  EXPECT_EQ(joint_distance(zero, ArmConfig{3, 4, 0, 0, 0, 0}), 5.0);
  EXPECT_EQ(joint_distance(zero, zero), 0.0);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const auto draw = [&] {
    ArmConfig q;
    for (double& x : q) x = u(rng);
    return q;
  };
  for (int i = 0; i < 200; ++i) {
    const ArmConfig a = draw(), b = draw(), c = draw();
    EXPECT_EQ(joint_distance(a, b), joint_distance(b, a));
    EXPECT_LE(joint_distance(a, c), joint_distance(a, b) + joint_distance(b, c) + 1e-12);
    double squares = 0.0;  // the slow reference: the norm of the difference
    for (int k = 0; k < kArmDof; ++k) squares += (a[k] - b[k]) * (a[k] - b[k]);
    EXPECT_NEAR(joint_distance(a, b), std::sqrt(squares), 1e-12);
  }
}

TEST(Types, MakePoseNormalisesItsRotation) {
  const Pose T = make_pose(Vec3(1, 2, 3), Quat(2.0, 0.0, 0.0, 2.0));  // 90 deg about z, not unit
  EXPECT_EQ(T.translation(), Vec3(1, 2, 3));
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  EXPECT_TRUE((T * Vec3(1, 0, 0)).isApprox(Vec3(1, 3, 3), 1e-12));
}

TEST(Types, CheckNamesTheConditionWhereAndWhy) {
  try {
    const int voxels = 3;
    CANOPY_CHECK(voxels == 4, "voxels: " << voxels);
    ADD_FAILURE() << "no throw";
  } catch (const InternalError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("types_test.cpp:"), std::string::npos) << what;
    EXPECT_NE(what.find("check failed: voxels == 4 (voxels: 3)"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(CANOPY_CHECK(1 + 1 == 2, ""));
}

}  // namespace
}  // namespace canopy
