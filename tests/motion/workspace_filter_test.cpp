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

// The filter as it was before positions were decided by bounds (issue 47): every position
// along the view measured, smallest shift first. The slow, obviously correct reference.
FilteredView filter_reference(const WorkspaceFilter& f, const BasePose& base, const Pose& T_world_camera,
                              const ArmConfig& seed, const CollisionChecker* checker) {
  const WorkspaceParams& p = f.params();
  std::vector<double> shifts = {0.0};
  const int n_fwd = static_cast<int>(std::floor(p.max_forward_shift_m / p.shift_step_m + 1e-9));
  const int n_back = static_cast<int>(std::floor(p.max_backward_shift_m / p.shift_step_m + 1e-9));
  for (int k = 1; k <= std::max(n_fwd, n_back); ++k) {
    if (k <= n_fwd) shifts.push_back(k * p.shift_step_m);
    if (k <= n_back) shifts.push_back(-k * p.shift_step_m);
  }
  FilteredView out;
  bool any_workspace = false, any_ik = false;
  for (double t : shifts) {
    Pose T = T_world_camera;
    T.translation() = T_world_camera.translation() + t * T_world_camera.linear().col(2);
    if (!f.in_workspace(base, T.translation())) continue;
    any_workspace = true;
    const IkResult ik = f.model().camera_ik(base, T, seed);
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

TEST(WorkspaceFilter, BoundsDecideAsMeasuringEveryPosition) {
  // Random views around the arm, from deep inside its workspace to far beyond it, with and
  // without obstacles: the filter's verdict, pose, shift and joints are the reference's, bit
  // for bit (the bounds only skip queries whose answer they know).
  std::mt19937 rng(47);
  const BasePose base{0.4, -0.2, 0.5};
  const Vec3 arm = (RobotModel::T_world_base(base) * model().T_base_arm()).translation();
  std::uniform_real_distribution<double> off(-1.0, 1.0), angle(-M_PI, M_PI);
  std::vector<Vec3> wall;  // a wall of voxels beside the arm: some IK solutions collide
  for (double y = -0.6; y <= 0.6; y += 0.03)
    for (double z = 0.0; z <= 1.2; z += 0.03) wall.push_back(arm + Vec3(0.35, y, z - 0.3));
  const CollisionChecker blocked(model(), CollisionParams{}, CollisionEnvironment::from_voxels(wall, 0.03));
  int verdicts[5] = {0, 0, 0, 0, 0};
  for (int i = 0; i < 1500; ++i) {
    Pose T = Pose::Identity();
    T.linear() = (Eigen::AngleAxisd(angle(rng), Vec3::UnitZ()) * Eigen::AngleAxisd(angle(rng), Vec3::UnitY()) *
                  Eigen::AngleAxisd(angle(rng), Vec3::UnitX()))
                     .toRotationMatrix();
    T.translation() = arm + Vec3(off(rng), off(rng), 0.5 * off(rng) + 0.3);
    const ArmConfig seed = random_config(rng);
    for (const CollisionChecker* checker : {static_cast<const CollisionChecker*>(nullptr), &blocked}) {
      const FilteredView fast = filter().filter(base, T, seed, checker);
      const FilteredView ref = filter_reference(filter(), base, T, seed, checker);
      ASSERT_EQ(fast.verdict, ref.verdict) << "view " << i;
      ++verdicts[static_cast<int>(fast.verdict)];
      EXPECT_EQ(fast.shift_m, ref.shift_m) << "view " << i;
      EXPECT_TRUE(fast.T_world_camera.matrix() == ref.T_world_camera.matrix()) << "view " << i;
      EXPECT_TRUE(fast.q == ref.q) << "view " << i;
    }
  }
  // Every verdict but invalid input occurs, so each path was compared.
  for (int v = 0; v < 4; ++v) EXPECT_GT(verdicts[v], 0) << to_string(static_cast<ViewVerdict>(v));
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
