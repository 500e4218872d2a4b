#include "canopy/motion/workspace_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/motion/collision.h"

namespace canopy::motion {
namespace {

const RobotModel& model() {
  static const RobotModel m = RobotModel::load(default_robot_config());
  return m;
}

const WorkspaceFilter& filter() {
  static const WorkspaceFilter f(model(), WorkspaceParams{});
  return f;
}

ArmConfig random_config(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  ArmConfig q;
  for (auto& v : q) v = u(rng);
  return q;
}

TEST(WorkspaceFilter, PointSetIsTheCameraWorkspace) {
  const auto& pts = filter().points_in_arm();
  EXPECT_GT(pts.size(), 40000u);
  const double arm_height = model().T_base_arm().translation().z();
  double max_r = 0;
  for (const Vec3& p : pts) {
    EXPECT_GE(p.z() + arm_height, WorkspaceParams{}.min_camera_height_m);
    max_r = std::max(max_r, (p - Vec3(0, 0, model().ur().dh().d[0])).norm());
  }
  // UR3 reach 0.5 m plus the tool and camera offsets.
  EXPECT_GT(max_r, 0.5);
  EXPECT_LT(max_r, 0.7);
}

TEST(WorkspaceFilter, ReachableViewsAreKeptInPlace) {
  std::mt19937 rng(3);
  const BasePose base{1.0, 0.5, 0.3};
  int kept = 0, in_place = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Pose T = model().camera_pose(base, random_config(rng));
    if (T.translation().z() < 0.1) continue;
    const FilteredView v = filter().filter(base, T, model().config().home);
    kept += v.kept();
    in_place += v.kept() && v.shift_m == 0.0;
    if (v.kept()) {
      EXPECT_LT((model().camera_pose(base, v.q).matrix() - v.T_world_camera.matrix()).norm(), 1e-6);
    }
  }
  EXPECT_GE(kept, static_cast<int>(0.95 * n) - 20);
  EXPECT_GE(in_place, static_cast<int>(0.9 * kept));
}

// Cameras beyond the arm's reach looking horizontally along the radial line through the
// mast axis. Looking outwards, they must be moved back (against the view) into the
// workspace; looking inwards, forward. Orientation never changes.
void check_moves(const WorkspaceFilter& f, double sign, int* tried, int* moved) {
  const BasePose base{0.5, -0.3, 0.7};
  const Pose T_world_arm = RobotModel::T_world_base(base) * model().T_base_arm();
  const Vec3 axis = T_world_arm.translation();
  for (int a = 0; a < 12; ++a) {
    for (double dz : {0.0, 0.15, 0.3}) {
      const double az = a * M_PI / 6;
      const Vec3 out(std::cos(az), std::sin(az), 0.0);
      Pose T = Pose::Identity();
      // Camera z (forward) = sign * out, camera y (down) = -world z, x = y cross z.
      const Vec3 z = sign * out, y = -Vec3::UnitZ();
      T.linear().col(0) = y.cross(z);
      T.linear().col(1) = y;
      T.linear().col(2) = z;
      T.translation() = axis + 0.70 * out + Vec3(0, 0, dz);
      ASSERT_FALSE(f.in_workspace(base, T.translation()));
      ++*tried;
      const FilteredView v = f.filter(base, T, model().config().home);
      if (!v.kept()) continue;
      ++*moved;
      // Outward views move back (negative shift), inward views forward.
      EXPECT_LT(v.shift_m * sign, 0.0);
      EXPECT_LT((v.T_world_camera.linear() - T.linear()).norm(), 1e-12);
      EXPECT_LT((v.T_world_camera.translation() - (T.translation() + v.shift_m * z)).norm(), 1e-12);
      EXPECT_LT((model().camera_pose(base, v.q).matrix() - v.T_world_camera.matrix()).norm(), 1e-6);
    }
  }
}

TEST(WorkspaceFilter, ViewsBeyondReachAreMovedAlongTheirViewingDirection) {
  int tried = 0, moved = 0;
  check_moves(filter(), +1.0, &tried, &moved);  // looking outwards: moved back
  EXPECT_GE(moved, tried * 9 / 10) << moved << " of " << tried;
  // Looking inwards the wrist must fold back, which the UR3 only manages well inside its
  // reach: allow longer forward moves.
  WorkspaceParams p;
  p.max_forward_shift_m = 0.4;
  const WorkspaceFilter longer(model(), p);
  tried = moved = 0;
  check_moves(longer, -1.0, &tried, &moved);
  EXPECT_GE(moved, tried / 2) << moved << " of " << tried;
}

TEST(WorkspaceFilter, ViewsThatMissTheWorkspaceAreDiscarded) {
  const BasePose base{0, 0, 0};
  Pose far = Pose::Identity();
  far.translation() = Vec3(3.0, 0.0, 1.0);
  EXPECT_EQ(filter().filter(base, far, model().config().home).verdict, ViewVerdict::kOutsideWorkspace);
  // Beyond the arm's reach, looking away from it: the line never meets the workspace.
  Pose away = Pose::Identity();
  away.linear() = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX()).toRotationMatrix();  // z -> +y
  away.translation() = Vec3(0.2, 0.9, 0.9);
  ASSERT_GT(away.linear().col(2).y(), 0.99);
  EXPECT_EQ(filter().filter(base, away, model().config().home).verdict, ViewVerdict::kOutsideWorkspace);
  // Facing the robot but further than the largest forward move: still discarded.
  Pose facing = away;
  facing.linear() = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()).toRotationMatrix();  // z -> -y
  facing.translation().y() = 1.2;
  EXPECT_EQ(filter().filter(base, facing, model().config().home).verdict, ViewVerdict::kOutsideWorkspace);
  Pose nan = facing;
  nan(1, 3) = std::nan("");
  EXPECT_EQ(filter().filter(base, nan, model().config().home).verdict, ViewVerdict::kInvalidInput);
}

TEST(WorkspaceFilter, CollisionCheckedSurvivors) {
  const BasePose base{0, 0, 0};
  const ArmConfig q = model().config().home;
  const Pose T = model().camera_pose(base, q);
  // Voxels filling a ball around the camera: every IK solution puts the camera there.
  std::vector<Vec3> ball;
  for (double x = -0.3; x <= 0.3; x += 0.02)
    for (double y = -0.3; y <= 0.3; y += 0.02)
      for (double z = -0.3; z <= 0.3; z += 0.02)
        if (Vec3(x, y, z).norm() < 0.3) ball.push_back(T.translation() + Vec3(x, y, z));
  const CollisionChecker blocked(model(), CollisionParams{}, CollisionEnvironment::from_voxels(ball, 0.02));
  EXPECT_EQ(filter().filter(base, T, q, &blocked).verdict, ViewVerdict::kInCollision);
  const CollisionChecker free(model(), CollisionParams{});
  EXPECT_TRUE(filter().filter(base, T, q, &free).kept());
  WorkspaceParams bad;
  bad.shift_step_m = 0.0;
  EXPECT_THROW(WorkspaceFilter(model(), bad), InputError);
}

}  // namespace
}  // namespace canopy::motion
