#include "canopy/motion/base_follower.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {
namespace {

struct RunResult {
  bool done = false;
  int steps = 0;
  BasePose final_pose;
  double max_abs_v = 0, max_abs_w = 0, max_dv = 0, max_dw = 0;
};

// Integrates the unicycle exactly for constant (v, w) over dt, optionally with a first-order
// lag between the command and the actual velocity (like a velocity servo).
RunResult run(const BaseFollowerParams& p, const BasePose& start, std::vector<BasePose> wps, double dt,
              double lag_s = 0.0, int max_steps = 20000) {
  BaseFollower f(p, std::move(wps));
  BasePose s = start;
  RunResult r;
  double v_prev = 0, w_prev = 0, v_act = 0, w_act = 0;
  for (int i = 0; i < max_steps; ++i) {
    const BaseCommand c = f.update(s, dt);
    EXPECT_TRUE(c.fault.empty()) << c.fault;
    r.max_abs_v = std::max(r.max_abs_v, std::abs(c.v_m_s));
    r.max_abs_w = std::max(r.max_abs_w, std::abs(c.omega_rad_s));
    r.max_dv = std::max(r.max_dv, std::abs(c.v_m_s - v_prev) / dt);
    r.max_dw = std::max(r.max_dw, std::abs(c.omega_rad_s - w_prev) / dt);
    v_prev = c.v_m_s;
    w_prev = c.omega_rad_s;
    r.steps = i;
    if (c.done) {
      r.done = true;
      break;
    }
    const double k = lag_s > 0 ? 1.0 - std::exp(-dt / lag_s) : 1.0;
    v_act += k * (c.v_m_s - v_act);
    w_act += k * (c.omega_rad_s - w_act);
    if (std::abs(w_act) < 1e-12) {
      s.x_m += v_act * dt * std::cos(s.yaw_rad);
      s.y_m += v_act * dt * std::sin(s.yaw_rad);
    } else {
      const double y1 = s.yaw_rad + w_act * dt;
      s.x_m += v_act / w_act * (std::sin(y1) - std::sin(s.yaw_rad));
      s.y_m -= v_act / w_act * (std::cos(y1) - std::cos(s.yaw_rad));
      s.yaw_rad = wrap_angle(y1);
    }
  }
  r.final_pose = s;
  return r;
}

void expect_reached(const BaseFollowerParams& p, const RunResult& r, const BasePose& goal) {
  ASSERT_TRUE(r.done) << "did not terminate";
  EXPECT_LE(std::hypot(r.final_pose.x_m - goal.x_m, r.final_pose.y_m - goal.y_m), p.position_tolerance_m);
  EXPECT_LE(std::abs(wrap_angle(r.final_pose.yaw_rad - goal.yaw_rad)), p.yaw_tolerance_rad);
  EXPECT_LE(r.max_abs_v, p.max_speed_m_s + 1e-12);
  EXPECT_LE(r.max_abs_w, p.max_yaw_rate_rad_s + 1e-12);
  EXPECT_LE(r.max_dv, p.max_accel_m_s2 + 1e-9);
  EXPECT_LE(r.max_dw, p.max_yaw_accel_rad_s2 + 1e-9);
}

TEST(BaseFollower, ReachesSingleGoals) {
  const BaseFollowerParams p;
  const BasePose start{0, 0, 0};
  const std::vector<BasePose> goals = {
      {2.0, 0.0, 0.0},       // straight ahead
      {-0.3, 0.0, 0.0},      // close behind: reverse
      {-3.0, 1.0, 2.5},      // far behind: turn around
      {0.0, 1.0, -1.0},      // sideways
      {0.0, 0.0, M_PI},      // turn in place only
      {0.005, 0.0, 0.0},     // already within tolerance
      {0.03, 0.03, 0.4},     // a small correction
  };
  for (const auto& g : goals) {
    SCOPED_TRACE(::testing::Message() << "goal " << g.x_m << "," << g.y_m << "," << g.yaw_rad);
    expect_reached(p, run(p, start, {g}, 0.01), g);
  }
}

TEST(BaseFollower, FollowsAPolylineAndStops) {
  const BaseFollowerParams p;
  const std::vector<BasePose> wps = {{1, 0, 0}, {1, 1, 0}, {3, 1, 0}, {3, -2, 0}, {0.5, -2, M_PI / 2}};
  const RunResult r = run(p, {0, 0, 0}, wps, 0.01);
  expect_reached(p, r, wps.back());
}

TEST(BaseFollower, RandomGoalsWithServoLagAndCoarseSteps) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-3.0, 3.0), yaw(-M_PI, M_PI);
  const BaseFollowerParams p;
  for (int trial = 0; trial < 40; ++trial) {
    const BasePose start{pos(rng), pos(rng), yaw(rng)};
    const BasePose goal{pos(rng), pos(rng), yaw(rng)};
    const double dt = trial % 2 ? 0.002 : 0.02;
    const double lag = trial % 3 == 0 ? 0.02 : 0.0;
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    expect_reached(p, run(p, start, {goal}, dt, lag, 200000), goal);
  }
}

TEST(BaseFollower, RespectsTighterLimits) {
  BaseFollowerParams p;
  p.max_speed_m_s = 0.3;
  p.max_accel_m_s2 = 0.2;
  p.max_yaw_rate_rad_s = 0.5;
  p.max_yaw_accel_rad_s2 = 0.4;
  const BasePose goal{1.5, -0.7, 2.0};
  expect_reached(p, run(p, {0, 0, 0}, {goal}, 0.01, 0.0, 100000), goal);
}

TEST(BaseFollower, BadInput) {
  const BaseFollowerParams p;
  EXPECT_THROW(BaseFollower(p, {}), InputError);
  EXPECT_THROW(BaseFollower(p, {{std::nan(""), 0, 0}}), InputError);
  BaseFollowerParams bad;
  bad.max_speed_m_s = -1;
  EXPECT_THROW(BaseFollower(bad, {{1, 0, 0}}), InputError);

  BaseFollower f(p, {{1, 0, 0}});
  BaseCommand c = f.update({std::nan(""), 0, 0}, 0.01);
  EXPECT_FALSE(c.fault.empty());
  EXPECT_EQ(c.v_m_s, 0.0);
  EXPECT_FALSE(c.done);
  c = f.update({0, 0, 0}, 0.0);
  EXPECT_FALSE(c.fault.empty());
  c = f.update({0, 0, 0}, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(c.fault.empty());
  c = f.update({0, 0, 0}, 0.01);
  EXPECT_TRUE(c.fault.empty());
}

TEST(BaseFollower, ParamsFromYamlAndRobot) {
  YamlReader y = YamlReader::load_string("max_speed_m_s: 0.5\nwaypoint_radius_m: 0.2\n", "test");
  const BaseFollowerParams p = params_from_yaml<BaseFollowerParams>(y);
  y.finish();
  EXPECT_EQ(p.max_speed_m_s, 0.5);
  EXPECT_EQ(p.waypoint_radius_m, 0.2);
  EXPECT_EQ(p.max_yaw_rate_rad_s, BaseFollowerParams{}.max_yaw_rate_rad_s);

  YamlReader bad = YamlReader::load_string("max_accel_m_s2: 0\n", "test");
  EXPECT_THROW(params_from_yaml<BaseFollowerParams>(bad), InputError);

  const RobotConfig robot = default_robot_config();
  const BaseFollowerParams r = BaseFollowerParams::from_robot(robot);
  EXPECT_EQ(r.max_speed_m_s, robot.base_max_speed_m_s);
  EXPECT_EQ(r.max_yaw_accel_rad_s2, robot.base_max_yaw_accel_rad_s2);
  // The struct defaults are the Husky limits in robot.yaml.
  EXPECT_EQ(r.max_speed_m_s, BaseFollowerParams{}.max_speed_m_s);
  EXPECT_EQ(r.max_yaw_rate_rad_s, BaseFollowerParams{}.max_yaw_rate_rad_s);
  EXPECT_EQ(r.max_accel_m_s2, BaseFollowerParams{}.max_accel_m_s2);
  EXPECT_EQ(r.max_yaw_accel_rad_s2, BaseFollowerParams{}.max_yaw_accel_rad_s2);
}

}  // namespace
}  // namespace canopy::motion
