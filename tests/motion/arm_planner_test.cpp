#include "canopy/motion/arm_planner.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <random>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {
namespace {

const RobotModel& model() {
  static const RobotModel m = RobotModel::load(default_robot_config());
  return m;
}

// A pillar of voxels beside the robot, in the way of many straight joint-space moves.
std::shared_ptr<const CollisionEnvironment> pillar() {
  std::vector<Vec3> v;
  const double res = 0.02;
  for (double x = 0.10; x <= 0.30; x += res)
    for (double y = 0.42; y <= 0.52; y += res)
      for (double z = 0.0; z <= 1.5; z += res) v.emplace_back(x, y, z);
  return CollisionEnvironment::from_voxels(v, res);
}

class ArmPlannerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { seed_planner_rng(42); }
  const BasePose base_{0, 0, 0};
  CollisionChecker checker_{model(), CollisionParams{}, pillar()};
};

// Dense check of a result: starts and ends where asked, every step collision-free, the
// trajectory within the joint limits.
void expect_valid_plan(const CollisionChecker& checker, const BasePose& base, const PlanResult& r,
                       const ArmConfig& start) {
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  EXPECT_LT(joint_distance(r.path.front(), start), 1e-12);
  EXPECT_LT(joint_distance(r.path.back(), r.goal), 1e-12);
  const ArmTrajectory& t = r.trajectory;
  const ArmLimits& lim = model().limits();
  for (double time = 0.0; time <= t.duration(); time += 0.005) {
    const ArmReference ref = t.sample(time);
    ASSERT_FALSE(checker.in_collision(base, ref.q)) << "trajectory in collision at t = " << time;
    for (int i = 0; i < kArmDof; ++i) {
      EXPECT_LE(std::abs(ref.qd[i]), lim.max_velocity[i] * (1 + 1e-9));
      EXPECT_LE(std::abs(ref.qdd[i]), lim.max_acceleration[i] * (1 + 1e-9));
    }
  }
  EXPECT_LT(joint_distance(t.sample(t.duration()).q, r.goal), 1e-9);
}

// Goals are camera poses of random collision-free configurations (all IK branches offered).
TEST_F(ArmPlannerTest, RandomReachableGoalsAreMostlyPlanned) {
  const ArmPlanner planner(checker_, PlannerParams{});
  const ArmConfig start = model().config().home;
  ASSERT_FALSE(checker_.in_collision(base_, start));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  int goals = 0, solved = 0, via_ompl = 0;
  while (goals < 25) {
    ArmConfig q;
    for (auto& v : q) v = u(rng);
    // Each joint at the 2*pi equivalent nearest the start, as IK goals are: with +-2*pi
    // joint ranges the other equivalents are often only reachable through the robot.
    for (int i = 0; i < kArmDof; ++i) q[i] = start[i] + std::remainder(q[i] - start[i], 2 * M_PI);
    if (!model().within_limits(q) || checker_.in_collision(base_, q)) continue;
    ++goals;
    const PlanResult r = planner.plan_to_camera_pose(base_, start, model().camera_pose(base_, q));
    if (!r.ok()) continue;
    ++solved;
    via_ompl += !r.direct;
    expect_valid_plan(checker_, base_, r, start);
  }
  EXPECT_GE(solved, 24) << "OMPL 2denvs-style threshold: >= 95% success";
  EXPECT_GE(via_ompl, 1) << "the pillar should force some non-straight paths";
}

TEST_F(ArmPlannerTest, CameraPoseGoal) {
  const ArmPlanner planner(checker_, PlannerParams{});
  const ArmConfig start = model().config().home;
  // A camera pose reached by a known collision-free configuration.
  const ArmConfig q_goal = {0.2, -1.6, 1.4, -1.2, -1.4, 0.3};
  ASSERT_FALSE(checker_.in_collision(base_, q_goal));
  const Pose goal = model().camera_pose(base_, q_goal);
  const PlanResult r = planner.plan_to_camera_pose(base_, start, goal);
  expect_valid_plan(checker_, base_, r, start);
  EXPECT_TRUE(pose_within(model().camera_pose(base_, r.goal), goal, 1e-6, 1e-6));
}

TEST_F(ArmPlannerTest, FailuresComeBackAsStatuses) {
  const ArmPlanner planner(checker_, PlannerParams{});
  const ArmConfig start = model().config().home;
  Pose goal = model().camera_pose(base_, start);

  Pose nan_goal = goal;
  nan_goal(0, 3) = std::nan("");
  EXPECT_EQ(planner.plan_to_camera_pose(base_, start, nan_goal).status, PlanStatus::kInvalidInput);
  ArmConfig nan_start = start;
  nan_start[0] = std::nan("");
  EXPECT_EQ(planner.plan_to_camera_pose(base_, nan_start, goal).status, PlanStatus::kInvalidInput);
  ArmConfig out_of_limits = start;
  out_of_limits[2] = 3.5;
  EXPECT_EQ(planner.plan_to_configs(base_, out_of_limits, {start}).status, PlanStatus::kInvalidInput);
  EXPECT_EQ(planner.plan_to_configs(base_, start, {}).status, PlanStatus::kInvalidInput);
  EXPECT_EQ(planner.plan_to_configs({std::nan(""), 0, 0}, start, {start}).status, PlanStatus::kInvalidInput);

  Pose far = goal;
  far.translation() += Vec3(2.0, 0, 0);
  const PlanResult no_ik = planner.plan_to_camera_pose(base_, start, far);
  EXPECT_EQ(no_ik.status, PlanStatus::kNoIk);
  EXPECT_FALSE(no_ik.message.empty());

  // Goal camera inside the pillar.
  Pose in_pillar = goal;
  in_pillar.translation() = Vec3(0.2, 0.44, 0.9);
  in_pillar.linear() = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX()).toRotationMatrix();  // looking +y
  const PlanResult gic = planner.plan_to_camera_pose(base_, start, in_pillar);
  EXPECT_EQ(gic.status, PlanStatus::kGoalInCollision) << to_string(gic.status) << " " << gic.message;

  // Start in collision: a voxel where the camera is.
  const Vec3 cam = model().camera_pose(base_, start).translation();
  const CollisionChecker blocked(model(), CollisionParams{}, CollisionEnvironment::from_voxels({cam}, 0.02));
  PlannerParams no_repair;
  no_repair.repair_start = false;
  const ArmPlanner blocked_planner(blocked, no_repair);
  const PlanResult sic = blocked_planner.plan_to_configs(base_, start, {{0.2, -1.6, 1.4, -1.2, -1.4, 0.3}});
  EXPECT_EQ(sic.status, PlanStatus::kStartInCollision);
  EXPECT_NE(sic.message.find("map"), std::string::npos) << sic.message;

  // The base itself in collision.
  const CollisionChecker base_blocked(model(), CollisionParams{},
                                      CollisionEnvironment::from_voxels({Vec3(0, 0, 0.2)}, 0.02));
  EXPECT_EQ(ArmPlanner(base_blocked, PlannerParams{}).plan_to_configs(base_, start, {start}).status,
            PlanStatus::kStartInCollision);

  // A start a hair past a joint limit (servo overshoot) is clamped; further out it is invalid.
  ArmConfig overshoot = start;
  overshoot[5] = model().limits().upper[5] + 0.005;
  const PlanResult clamped = planner.plan_to_configs(base_, overshoot, {start});
  ASSERT_TRUE(clamped.ok()) << clamped.message;
  EXPECT_EQ(clamped.path.front()[5], model().limits().upper[5]);
  overshoot[5] = model().limits().upper[5] + 0.1;
  EXPECT_EQ(planner.plan_to_configs(base_, overshoot, {start}).status, PlanStatus::kInvalidInput);

  // Timeout: a tiny budget and no straight-line shortcut.
  PlannerParams rushed;
  rushed.time_limit_s = 1e-5;
  rushed.try_direct_first = false;
  const ArmPlanner rushed_planner(checker_, rushed);
  const PlanResult to = rushed_planner.plan_to_configs(base_, start, {{-2.0, -1.0, 2.0, -1.0, 1.0, 0.0}});
  EXPECT_EQ(to.status, PlanStatus::kTimeout) << to.message;

  // The iteration budget decides, not the clock: one iteration cannot connect this goal.
  PlannerParams short_budget;
  short_budget.max_iterations = 1;
  short_budget.try_direct_first = false;
  const PlanResult tb = ArmPlanner(checker_, short_budget).plan_to_configs(base_, start, {{-2.0, -1.0, 2.0, -1.0, 1.0, 0.0}});
  EXPECT_EQ(tb.status, PlanStatus::kTimeout) << tb.message;
  EXPECT_NE(tb.message.find("iterations"), std::string::npos) << tb.message;
}

// The same request and seed give the same path, whatever ran before it in the process.
TEST_F(ArmPlannerTest, SeedDecidesThePath) {
  const ArmConfig start = model().config().home;
  const ArmConfig goal = {-1.2, -1.3, 1.2, -1.5, -1.4, 0.5};
  PlannerParams p;
  p.try_direct_first = false;
  p.simplify = false;  // the raw tree path shows the seed (simplified paths may coincide)
  const ArmPlanner planner(checker_, p);
  const PlanResult a = planner.plan_to_configs(base_, start, {goal}, 7);
  const PlanResult other = planner.plan_to_configs(base_, start, {goal}, 8);
  const PlanResult b = planner.plan_to_configs(base_, start, {goal}, 7);
  ASSERT_TRUE(a.ok() && b.ok() && other.ok()) << a.message << b.message << other.message;
  ASSERT_EQ(a.path.size(), b.path.size());
  for (size_t k = 0; k < a.path.size(); ++k) EXPECT_EQ(a.path[k], b.path[k]) << "waypoint " << k;
  // A different seed explores differently (same endpoints, another path).
  bool differs = a.path.size() != other.path.size();
  for (size_t k = 0; !differs && k < a.path.size(); ++k) differs = a.path[k] != other.path[k];
  EXPECT_TRUE(differs);
}

// The planner's motion check with its states shared by two threads gives OMPL's own verdict
// (one thread): 2,000 motions of 16 to 40 states from free states, tested 0.15 rad apart so
// that an obstacle is often met by one or two of them (a check that skipped some states would
// call such motions free).
TEST_F(ArmPlannerTest, SharedMotionChecksGiveOmplsVerdicts) {
  Rng rng(31);
  const ArmConfig home = model().config().home;
  PlannerParams one, shared;
  one.motion_check_resolution_rad = shared.motion_check_resolution_rad = 0.15;
  one.motion_check_threads = 1;
  shared.motion_check_threads = 2;
  tbb::task_arena two(2);
  int valid = 0, invalid = 0;
  for (int m = 0; m < 2000; ++m) {
    ArmConfig a, b, d;
    for (int i = 0; i < kArmDof; ++i) a[i] = home[i] + rng.uniform(-1.5, 1.5);
    if (!model().within_limits(a) || checker_.in_collision(base_, a, BodySet::kArmOnly)) continue;
    for (int i = 0; i < kArmDof; ++i) d[i] = rng.normal();
    const double length = rng.uniform(2.4, 6.0) / joint_distance(d, ArmConfig{});
    for (int i = 0; i < kArmDof; ++i) b[i] = a[i] + length * d[i];
    bool by_one = false, by_two = false;
    two.execute([&] {
      by_one = planner_checks_motion(checker_, one, base_, a, b);
      by_two = planner_checks_motion(checker_, shared, base_, a, b);
    });
    ASSERT_EQ(by_one, by_two) << "motion " << m;
    (by_one ? valid : invalid) += 1;
  }
  EXPECT_GT(valid, 200);
  EXPECT_GT(invalid, 100);
}

// Testing a motion's states on two threads gives the planning thread's verdicts, so every plan
// is the same: raw tree paths (no shortcuts) and simplified ones, reached and failed goals, in an
// arena of two threads whatever the machine has.
TEST_F(ArmPlannerTest, MotionCheckThreadsDoNotChangeThePlans) {
  Rng rng(5);
  const ArmConfig start = model().config().home;
  std::vector<ArmConfig> goals;  // as RandomReachableGoalsAreMostlyPlanned draws them
  while (goals.size() < 6) {
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = start[i] + std::remainder(rng.uniform(-M_PI, M_PI) - start[i], 2 * M_PI);
    if (model().within_limits(q) && !checker_.in_collision(base_, q)) goals.push_back(q);
  }
  tbb::task_arena two(2);
  int failed = 0;
  for (const bool simplify : {false, true})
    for (const int budget : {2, 20000}) {
      PlannerParams one, shared;
      one.try_direct_first = shared.try_direct_first = false;
      one.simplify = shared.simplify = simplify;
      one.max_iterations = shared.max_iterations = budget;
      one.motion_check_threads = 1;
      shared.motion_check_threads = 2;
      for (std::size_t g = 0; g < goals.size(); ++g) {
        PlanResult a, b;
        two.execute([&] {
          a = ArmPlanner(checker_, one).plan_to_configs(base_, start, {goals[g]}, 11 + g);
          b = ArmPlanner(checker_, shared).plan_to_configs(base_, start, {goals[g]}, 11 + g);
        });
        ASSERT_EQ(a.status, b.status) << "goal " << g << ": " << a.message << " / " << b.message;
        failed += !a.ok();
        ASSERT_EQ(a.path.size(), b.path.size()) << "goal " << g;
        for (std::size_t k = 0; k < a.path.size(); ++k) EXPECT_EQ(a.path[k], b.path[k]) << "goal " << g << ", waypoint " << k;
      }
    }
  EXPECT_GT(failed, 0);   // the short budget ends some searches
  EXPECT_LT(failed, 24);  // and the full one finds paths
}

// A request's recorded iterations decide its outcome under any budget: with exactly that many
// the same path, with one fewer a timeout, with more the same path again; a straight line or a
// goal in collision ran no iteration, a search out of budget used all of it. This is what lets
// a budget's effect be read off recorded missions (docs/performance.md).
TEST_F(ArmPlannerTest, RecordedIterationsDecideTheOutcomeUnderAnyBudget) {
  Rng rng(17);
  const ArmConfig start = model().config().home;
  int searched = 0, multi = 0;
  for (int g = 0; g < 40 && searched < 8; ++g) {
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = start[i] + std::remainder(rng.uniform(-M_PI, M_PI) - start[i], 2 * M_PI);
    if (!model().within_limits(q) || checker_.in_collision(base_, q)) continue;
    PlannerParams p;
    p.try_direct_first = false;
    p.simplify = false;
    const PlanResult full = ArmPlanner(checker_, p).plan_to_configs(base_, start, {q}, 3 + g);
    if (!full.ok()) continue;
    ++searched;
    ASSERT_GE(full.iterations, 1);
    ASSERT_LE(full.iterations, p.max_iterations);
    multi += full.iterations > 1;
    for (const int budget : {full.iterations, full.iterations + 37}) {
      p.max_iterations = budget;
      const PlanResult same = ArmPlanner(checker_, p).plan_to_configs(base_, start, {q}, 3 + g);
      ASSERT_TRUE(same.ok()) << "goal " << g << ", budget " << budget << ": " << same.message;
      EXPECT_EQ(same.iterations, full.iterations);
      ASSERT_EQ(same.path, full.path) << "goal " << g << ", budget " << budget;
    }
    if (full.iterations > 1) {
      p.max_iterations = full.iterations - 1;
      const PlanResult short_of = ArmPlanner(checker_, p).plan_to_configs(base_, start, {q}, 3 + g);
      EXPECT_EQ(short_of.status, PlanStatus::kTimeout) << "goal " << g;
      EXPECT_EQ(short_of.iterations, full.iterations - 1);
    }
  }
  EXPECT_GE(searched, 4);
  EXPECT_GE(multi, 2);  // some searches needed more than one iteration
  PlannerParams direct;
  const ArmConfig near = {start[0] + 0.05, start[1], start[2], start[3], start[4], start[5]};
  const PlanResult line = ArmPlanner(checker_, direct).plan_to_configs(base_, start, {near}, 1);
  ASSERT_TRUE(line.ok() && line.direct) << line.message;
  EXPECT_EQ(line.iterations, 0);
}

// straight_plan gives plan_to_configs' result exactly when that is the straight line, and
// nothing otherwise (a search, or a failure), on requests of all three kinds.
TEST_F(ArmPlannerTest, StraightPlanIsThePlanWhenItIsTheStraightLine) {
  Rng rng(23);
  const ArmConfig home = model().config().home;
  const ArmPlanner planner(checker_, PlannerParams{});
  int straight = 0, searched = 0, failed = 0;
  for (int g = 0; g < 60; ++g) {
    ArmConfig start = home, q;
    if (g % 2) {  // a nearby start, so that straight lines are common
      for (int i = 0; i < kArmDof; ++i) start[i] = home[i] + rng.uniform(-0.4, 0.4);
      if (!model().within_limits(start) || checker_.in_collision(base_, start)) continue;
    }
    const double reach = g % 3 == 0 ? 0.5 : M_PI;
    for (int i = 0; i < kArmDof; ++i) q[i] = start[i] + rng.uniform(-reach, reach);
    const PlanResult full = planner.plan_to_configs(base_, start, {q}, 5 + g);
    const std::optional<PlanResult> line = planner.straight_plan(base_, start, {q}, 5 + g);
    if (full.ok() && full.direct) {
      ++straight;
      ASSERT_TRUE(line.has_value()) << "goal " << g;
      EXPECT_TRUE(line->direct);
      EXPECT_EQ(line->path, full.path);
      EXPECT_EQ(line->goal, full.goal);
    } else {
      (full.ok() ? searched : failed) += 1;
      EXPECT_FALSE(line.has_value()) << "goal " << g << ": " << to_string(full.status);
    }
  }
  EXPECT_GE(straight, 3);
  EXPECT_GE(searched, 2);
  EXPECT_GE(failed, 1);
}

// ---- Start states in collision are repaired (FACTS 19, MoveIt's FixStartStateCollision) ----

// A state just inside a self-collision: the boundary between `free_q` and a self-colliding
// state found by a seeded search, approached by bisection (a wrist resting against the chassis
// after a servo settled it a hair past a goal is such a state).
ArmConfig just_inside_self_collision(const CollisionChecker& self_only, const BasePose& base, const ArmConfig& free_q,
                                     std::uint64_t seed) {
  Rng rng(seed);
  for (int tries = 0; tries < 100000; ++tries) {
    ArmConfig q;
    for (int i = 0; i < kArmDof; ++i) q[i] = free_q[i] + rng.uniform(-1.5, 1.5);
    if (!model().within_limits(q)) continue;
    const CollisionReport r = self_only.report(base, q);
    if (!r.in_collision) continue;
    bool self = true;
    for (const std::string& p : r.pairs) self = self && p.find("| map") == std::string::npos && p.find("| ground") == std::string::npos;
    if (!self) continue;
    ArmConfig a = free_q, b = q;  // a free, b in collision
    for (int k = 0; k < 40; ++k) {
      ArmConfig m;
      for (int i = 0; i < kArmDof; ++i) m[i] = 0.5 * (a[i] + b[i]);
      (self_only.in_collision(base, m) ? b : a) = m;
    }
    return b;
  }
  ADD_FAILURE() << "no self-collision found";
  return free_q;
}

// A repaired plan: it starts at the start in collision, its first segment leaves the collision
// for good (every state after the first free one is free), and the rest is a valid plan.
void expect_repaired_plan(const CollisionChecker& checker, const BasePose& base, const PlanResult& r,
                          const ArmConfig& start) {
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  ASSERT_TRUE(r.repaired);
  ASSERT_EQ(r.repair.size(), 2u);
  EXPECT_LT(joint_distance(r.path.front(), start), 1e-12);
  EXPECT_LT(joint_distance(r.path[1], r.repair.back()), 1e-12);
  EXPECT_FALSE(checker.in_collision(base, r.repair.back()));
  bool out = false;
  const ArmTrajectory& t = r.trajectory;
  for (double time = 0.0; time <= t.duration(); time += 0.002) {
    const bool hit = checker.in_collision(base, t.sample(time).q);
    if (out) {
      ASSERT_FALSE(hit) << "back in collision at t = " << time;
    }
    out = out || !hit;
  }
  EXPECT_TRUE(out);
  EXPECT_LT(joint_distance(t.sample(t.duration()).q, r.goal), 1e-9);
}

TEST(StartRepair, AStartInSelfCollisionIsLeftByAShortMove) {
  const BasePose base{0, 0, 0};
  const CollisionChecker self_only(model(), CollisionParams{});
  const ArmConfig home = model().config().home;
  const ArmConfig goal = {0.2, -1.6, 1.4, -1.2, -1.4, 0.3};
  ASSERT_FALSE(self_only.in_collision(base, goal));
  int repaired = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const ArmConfig start = just_inside_self_collision(self_only, base, home, seed);
    ASSERT_TRUE(self_only.in_collision(base, start));
    PlannerParams off;
    off.repair_start = false;
    EXPECT_EQ(ArmPlanner(self_only, off).plan_to_configs(base, start, {goal}).status, PlanStatus::kStartInCollision);
    const ArmPlanner planner(self_only, PlannerParams{});
    const PlanResult r = planner.plan_to_configs(base, start, {goal}, 3);
    expect_repaired_plan(self_only, base, r, start);
    repaired += r.ok();
    EXPECT_NE(r.repair_note.find("left by jiggle"), std::string::npos) << r.repair_note;
    // A short move: within the jiggle of each joint's range.
    const ArmLimits& lim = model().limits();
    for (int i = 0; i < kArmDof; ++i)
      EXPECT_LE(std::abs(r.repair[1][i] - start[i]), PlannerParams{}.jiggle_fraction * (lim.upper[i] - lim.lower[i]) + 1e-12);
    // Deterministic for a seed.
    const PlanResult again = planner.plan_to_configs(base, start, {goal}, 3);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again.repair[1], r.repair[1]);
  }
  EXPECT_EQ(repaired, 5);
}

TEST(StartRepair, AStartInMapCollisionIsLeftByAShortMove) {
  const BasePose base{0, 0, 0};
  const ArmConfig home = model().config().home;
  // A voxel where the wrist camera is (a leaf brushed by the camera).
  const Pose cam = model().camera_pose(base, home);
  const std::shared_ptr<const CollisionEnvironment> env =
      CollisionEnvironment::from_voxels({cam.translation()}, 0.02);
  const CollisionChecker checker(model(), CollisionParams{}, env);
  const CollisionReport at = checker.report(base, home);
  ASSERT_TRUE(at.in_collision);
  ASSERT_NE(at.pairs.front().find("map"), std::string::npos) << at.pairs.front();
  const ArmConfig goal = {0.2, -1.6, 1.4, -1.2, -1.4, 0.3};
  ASSERT_FALSE(checker.in_collision(base, goal));
  const PlanResult r = ArmPlanner(checker, PlannerParams{}).plan_to_configs(base, home, {goal}, 5);
  expect_repaired_plan(checker, base, r, home);
  EXPECT_NE(r.repair_note.find("map"), std::string::npos) << r.repair_note;
}

TEST(StartRepair, WithoutANearbyFreeStateTheArmRetreatsHome) {
  const BasePose base{0, 0, 0};
  const CollisionChecker self_only(model(), CollisionParams{});
  const ArmConfig home = model().config().home;
  PlannerParams p;
  p.jiggle_fraction = 1e-7;  // no jiggle leaves it
  p.repair_attempts = 5;
  const ArmPlanner planner(self_only, p);
  int home_repairs = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const ArmConfig start = just_inside_self_collision(self_only, base, home, seed);
    const StartRepair rep = planner.repair_start(base, start, 1);
    ASSERT_TRUE(rep.needed);
    EXPECT_EQ(rep.samples, 5);
    if (!rep.ok) continue;
    EXPECT_EQ(rep.how, "home");
    EXPECT_EQ(rep.q, home);
    ++home_repairs;
  }
  // The start lies on the line from home to a collision: going back home leaves it.
  EXPECT_GE(home_repairs, 4);
  // A free start needs no repair.
  EXPECT_FALSE(planner.repair_start(base, home, 1).needed);
  // The base in collision: moving the arm cannot help.
  const CollisionChecker base_blocked(model(), CollisionParams{}, CollisionEnvironment::from_voxels({Vec3(0, 0, 0.2)}, 0.02));
  const PlanResult blocked = ArmPlanner(base_blocked, PlannerParams{}).plan_to_configs(base, home, {home});
  EXPECT_EQ(blocked.status, PlanStatus::kStartInCollision);
}

// Goals keep goal_self_clearance_m from the robot itself: a goal a hair outside a
// self-collision is refused, the servos would settle it touching.
TEST(StartRepair, GoalsTouchingTheRobotItselfAreRefused) {
  const BasePose base{0, 0, 0};
  const CollisionChecker self_only(model(), CollisionParams{});
  const ArmConfig home = model().config().home;
  const ArmConfig inside = just_inside_self_collision(self_only, base, home, 2);
  // Just outside: a little toward home.
  ArmConfig outside = inside;
  for (int i = 0; i < kArmDof; ++i) outside[i] = inside[i] + 1e-4 * (home[i] - inside[i]) / joint_distance(home, inside);
  ASSERT_FALSE(self_only.in_collision(base, outside));
  PlannerParams no_clearance;
  no_clearance.goal_self_clearance_m = 0.0;
  EXPECT_TRUE(ArmPlanner(self_only, no_clearance).plan_to_configs(base, home, {outside}).ok());
  const PlanResult r = ArmPlanner(self_only, PlannerParams{}).plan_to_configs(base, home, {outside});
  EXPECT_EQ(r.status, PlanStatus::kGoalInCollision) << r.message;
}

TEST(ArmPlannerParams, YamlAndRegistry) {
  YamlReader y = YamlReader::load_string("planner: PRM\ntime_limit_s: 2.5\n", "t");
  const PlannerParams p = params_from_yaml<PlannerParams>(y);
  y.finish();
  EXPECT_EQ(p.planner, "PRM");
  EXPECT_EQ(p.time_limit_s, 2.5);
  YamlReader bad = YamlReader::load_string("planner: NoSuchPlanner\n", "t");
  EXPECT_THROW(params_from_yaml<PlannerParams>(bad), InputError);
  EXPECT_GE(planner_names().size(), 10u);
  EXPECT_STREQ(to_string(PlanStatus::kGoalInCollision), "goal_in_collision");
}

TEST_F(ArmPlannerTest, OtherPlannersFromTheRegistry) {
  const ArmConfig start = model().config().home;
  const ArmConfig goal = {-1.2, -1.3, 1.2, -1.5, -1.4, 0.5};
  ASSERT_FALSE(checker_.in_collision(base_, goal));
  for (const char* name : {"RRT", "BiEST", "KPIECE1"}) {
    PlannerParams p;
    p.planner = name;
    p.try_direct_first = false;
    p.time_limit_s = 2.0;
    const PlanResult r = ArmPlanner(checker_, p).plan_to_configs(base_, start, {goal});
    SCOPED_TRACE(name);
    expect_valid_plan(checker_, base_, r, start);
  }
}

}  // namespace
}  // namespace canopy::motion
