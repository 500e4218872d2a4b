#include "canopy/motion/motion_config.h"

#include <cmath>
#include <type_traits>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::motion {

MotionConfig MotionConfig::defaults(const RobotConfig& robot) {
  MotionConfig c;
  c.base = BaseFollowerParams::from_robot(robot);
  return c;
}

namespace {

MotionConfig read(YamlReader& y, const RobotConfig& robot) {
  MotionConfig c = MotionConfig::defaults(robot);
  read_params(y, c);
  y.finish();
  return c;
}

}  // namespace

MotionConfig MotionConfig::load(const std::string& path, const RobotConfig& robot) {
  YamlReader y = YamlReader::load_file(path);
  return read(y, robot);
}

MotionConfig MotionConfig::load_string(const std::string& text, const std::string& name, const RobotConfig& robot) {
  YamlReader y = YamlReader::load_string(text, name);
  return read(y, robot);
}

}  // namespace canopy::motion
