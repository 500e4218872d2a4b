#include "canopy/motion/motion_config.h"

#include <gtest/gtest.h>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"

namespace canopy::motion {
namespace {

// configs/motion.yaml lists every setting at its default: loading it changes nothing.
TEST(MotionConfig, YamlDefaultsEqualStructDefaults) {
  const RobotConfig robot = default_robot_config();
  const MotionConfig from_file = MotionConfig::load(find_data_file("configs/motion.yaml"), robot);
  const MotionConfig defaults = MotionConfig::defaults(robot);
  EXPECT_EQ(yaml_text(params_to_yaml(from_file)), yaml_text(params_to_yaml(defaults)));
}

TEST(MotionConfig, PartialFilesAndErrors) {
  const RobotConfig robot = default_robot_config();
  const MotionConfig c = MotionConfig::load_string("planner:\n  time_limit_s: 3\ntour:\n  cost: cartesian\n", "t", robot);
  EXPECT_EQ(c.planner.time_limit_s, 3.0);
  EXPECT_EQ(c.tour.cost, "cartesian");
  EXPECT_EQ(c.planner.planner, "RRTConnect");
  EXPECT_EQ(c.base.max_speed_m_s, robot.base_max_speed_m_s);
  EXPECT_THROW(MotionConfig::load_string("planner:\n  time_limit: 3\n", "t", robot), InputError);  // typo
  EXPECT_THROW(MotionConfig::load_string("plannr: {}\n", "t", robot), InputError);
  EXPECT_THROW(MotionConfig::load_string("execution:\n  settle_time_s: -1\n", "t", robot), InputError);
  try {
    MotionConfig::load_string("workspace:\n  samples: 3\n", "motion.yaml", robot);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("motion.yaml"), std::string::npos) << e.what();
  }
  // Round trip: the saved settings load back to the same settings.
  const std::string saved = yaml_text(params_to_yaml(c));
  const MotionConfig back = MotionConfig::load_string(saved, "roundtrip", robot);
  EXPECT_EQ(yaml_text(params_to_yaml(back)), saved);
  EXPECT_EQ(back.planner.time_limit_s, 3.0);
}

}  // namespace
}  // namespace canopy::motion
