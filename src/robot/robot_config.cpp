#include "canopy/robot/robot_config.h"

#include <cmath>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"

namespace fs = std::filesystem;

namespace canopy {

namespace {

ArmConfig read_arm(YamlReader& y, const std::string& key, const ArmConfig& fallback, bool positive) {
  if (!y.has(key)) return fallback;
  const auto v = y.require<std::vector<double>>(key);
  y.check(v.size() == kArmDof, key, "must list 6 numbers (one per arm joint)");
  ArmConfig out{};
  for (int i = 0; i < kArmDof; ++i) {
    y.check(std::isfinite(v[i]), key, "must be finite");
    if (positive) y.check(v[i] > 0.0, key, "must be > 0");
    out[i] = v[i];
  }
  return out;
}

}  // namespace

RobotConfig RobotConfig::load(const std::string& yaml_path) {
  YamlReader y = YamlReader::load_file(yaml_path);
  RobotConfig c;
  const std::string urdf = y.require<std::string>("urdf");
  c.urdf_path = fs::absolute(fs::path(yaml_path).parent_path() / urdf).lexically_normal().string();
  if (!fs::exists(c.urdf_path)) y.fail("urdf", "names a file that does not exist (" + c.urdf_path + ")");
  c.camera_frame = y.get("camera_frame", c.camera_frame);
  c.tool_frame = y.get("tool_frame", c.tool_frame);
  c.arm_base_frame = y.get("arm_base_frame", c.arm_base_frame);
  c.base_joints = y.get("base_joints", c.base_joints);
  y.check(c.base_joints.size() == 3, "base_joints", "must name 3 joints (x, y, yaw)");
  c.arm_joints = y.get("arm_joints", c.arm_joints);
  y.check(c.arm_joints.size() == kArmDof, "arm_joints", "must name 6 joints");
  c.home = read_arm(y, "home", c.home, false);
  c.arm_max_velocity = read_arm(y, "arm_max_velocity", c.arm_max_velocity, true);
  c.arm_max_acceleration = read_arm(y, "arm_max_acceleration", c.arm_max_acceleration, true);
  c.arm_kp = read_arm(y, "arm_kp", c.arm_kp, true);
  c.arm_armature = read_arm(y, "arm_armature", c.arm_armature, true);
  auto positive = [&](const std::string& key, double fallback) {
    const double v = y.get(key, fallback);
    y.check(std::isfinite(v) && v > 0.0, key, "must be > 0");
    return v;
  };
  c.base_max_speed_m_s = positive("base_max_speed_m_s", c.base_max_speed_m_s);
  c.base_max_yaw_rate_rad_s = positive("base_max_yaw_rate_rad_s", c.base_max_yaw_rate_rad_s);
  c.base_max_accel_m_s2 = positive("base_max_accel_m_s2", c.base_max_accel_m_s2);
  c.base_max_yaw_accel_rad_s2 = positive("base_max_yaw_accel_rad_s2", c.base_max_yaw_accel_rad_s2);
  if (y.has("base_kv")) {
    const auto v = y.require<std::vector<double>>("base_kv");
    y.check(v.size() == 3 && v[0] > 0 && v[1] > 0 && v[2] > 0, "base_kv", "must list 3 positive gains");
    c.base_kv = {v[0], v[1], v[2]};
  }
  c.gravity_compensation = y.get("gravity_compensation", c.gravity_compensation);
  c.aisle_clearance_m = y.get("aisle_clearance_m", c.aisle_clearance_m);
  y.check(std::isfinite(c.aisle_clearance_m) && c.aisle_clearance_m >= 0.0, "aisle_clearance_m", "must be >= 0");
  y.finish();
  return c;
}

RobotConfig default_robot_config() { return RobotConfig::load(find_data_file("models/robot/robot.yaml")); }

}  // namespace canopy
