#include "canopy/motion/motion_config.h"

#include <cmath>
#include <type_traits>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {

ExecutionParams ExecutionParams::from_yaml(YamlReader& y, const ExecutionParams& d) {
  ExecutionParams p;
  p.position_tolerance_m = y.get("position_tolerance_m", d.position_tolerance_m);
  p.angle_tolerance_rad = y.get("angle_tolerance_rad", d.angle_tolerance_rad);
  p.settle_time_s = y.get("settle_time_s", d.settle_time_s);
  p.truth_check_period_s = y.get("truth_check_period_s", d.truth_check_period_s);
  try {
    p.validate();
  } catch (const InputError& e) {
    throw InputError(y.file() + ": " + e.what());
  }
  return p;
}

void ExecutionParams::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0.0)) throw InputError(std::string("execution: ") + name + " must be > 0");
  };
  positive(position_tolerance_m, "position_tolerance_m");
  positive(angle_tolerance_rad, "angle_tolerance_rad");
  positive(truth_check_period_s, "truth_check_period_s");
  if (!(std::isfinite(settle_time_s) && settle_time_s >= 0.0)) throw InputError("execution: settle_time_s must be >= 0");
}

MotionConfig MotionConfig::defaults(const RobotConfig& robot) {
  MotionConfig c;
  c.base = BaseFollowerParams::from_robot(robot);
  return c;
}

namespace {

MotionConfig read(YamlReader& y, const RobotConfig& robot) {
  MotionConfig c = MotionConfig::defaults(robot);
  c.seed = y.get("seed", c.seed);
  // Each section is read by its component's from_yaml, which rejects unknown keys.
  auto section = [&y](const char* name, auto& value) {
    YamlReader s = y.child(name);
    value = std::decay_t<decltype(value)>::from_yaml(s, value);
    s.finish();
  };
  section("base", c.base);
  section("collision", c.collision);
  section("planner", c.planner);
  section("trajectory", c.trajectory);
  section("workspace", c.workspace);
  section("tour", c.tour);
  section("execution", c.execution);
  y.finish();
  return c;
}

}  // namespace

MotionConfig MotionConfig::from_yaml(YamlReader& y, const RobotConfig& robot) { return read(y, robot); }

MotionConfig MotionConfig::load(const std::string& path, const RobotConfig& robot) {
  YamlReader y = YamlReader::load_file(path);
  return read(y, robot);
}

MotionConfig MotionConfig::load_string(const std::string& text, const std::string& name, const RobotConfig& robot) {
  YamlReader y = YamlReader::load_string(text, name);
  return read(y, robot);
}

nlohmann::json MotionConfig::to_json() const {
  nlohmann::json j;
  j["seed"] = seed;
  j["base"] = {{"max_speed_m_s", base.max_speed_m_s},
               {"max_yaw_rate_rad_s", base.max_yaw_rate_rad_s},
               {"max_accel_m_s2", base.max_accel_m_s2},
               {"max_yaw_accel_rad_s2", base.max_yaw_accel_rad_s2},
               {"position_tolerance_m", base.position_tolerance_m},
               {"yaw_tolerance_rad", base.yaw_tolerance_rad},
               {"settle_fraction", base.settle_fraction},
               {"waypoint_radius_m", base.waypoint_radius_m},
               {"heading_gain_per_s", base.heading_gain_per_s},
               {"distance_gain_per_s", base.distance_gain_per_s},
               {"braking_fraction", base.braking_fraction},
               {"turn_in_place_rad", base.turn_in_place_rad},
               {"reverse_max_distance_m", base.reverse_max_distance_m},
               {"stopped_speed_m_s", base.stopped_speed_m_s},
               {"stopped_yaw_rate_rad_s", base.stopped_yaw_rate_rad_s}};
  j["collision"] = {{"environment_padding_m", collision.environment_padding_m},
                    {"self_padding_m", collision.self_padding_m},
                    {"check_ground", collision.check_ground},
                    {"ground_height_m", collision.ground_height_m}};
  j["planner"] = {{"planner", planner.planner},
                  {"max_iterations", planner.max_iterations},
                  {"time_limit_s", planner.time_limit_s},
                  {"motion_check_resolution_rad", planner.motion_check_resolution_rad},
                  {"range_rad", planner.range_rad},
                  {"try_direct_first", planner.try_direct_first},
                  {"simplify", planner.simplify},
                  {"max_goal_configs", planner.max_goal_configs},
                  {"start_limit_tolerance_rad", planner.start_limit_tolerance_rad}};
  j["trajectory"] = {{"velocity_scale", trajectory.velocity_scale},
                     {"acceleration_scale", trajectory.acceleration_scale}};
  j["workspace"] = {{"samples", workspace.samples},
                    {"seed", workspace.seed},
                    {"membership_radius_m", workspace.membership_radius_m},
                    {"min_camera_height_m", workspace.min_camera_height_m},
                    {"max_forward_shift_m", workspace.max_forward_shift_m},
                    {"max_backward_shift_m", workspace.max_backward_shift_m},
                    {"shift_step_m", workspace.shift_step_m}};
  j["tour"] = {{"exact_max_views", tour.exact_max_views}, {"cost", tour.cost}};
  j["execution"] = {{"position_tolerance_m", execution.position_tolerance_m},
                    {"angle_tolerance_rad", execution.angle_tolerance_rad},
                    {"settle_time_s", execution.settle_time_s},
                    {"truth_check_period_s", execution.truth_check_period_s}};
  return j;
}

}  // namespace canopy::motion
