// The settings bundle: defaults equal the shipped configs, a saved bundle loads back to the
// same settings, and bad bundles are input errors.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/mission/settings.h"

namespace canopy::mission {
namespace {

TEST(Settings, ShippedBundleEqualsTheDefaults) {
  const RobotConfig robot = default_robot_config();
  const Settings shipped = Settings::load(default_settings_path(), robot);
  const Settings defaults = Settings::defaults(robot);
  EXPECT_EQ(shipped.to_yaml_text(), defaults.to_yaml_text());
  EXPECT_TRUE(shipped.nbv == defaults.nbv);
  EXPECT_TRUE(shipped.mission == defaults.mission);
}

TEST(Settings, SavedBundleLoadsBackToTheSameSettings) {
  const RobotConfig robot = default_robot_config();
  Settings s = Settings::defaults(robot);
  s.mission.loop.views_per_stop = 7;
  s.mission.stops.positions_m = {0.1, 0.7};
  s.nbv.frontier.max_targets = 42;
  s.motion.planner.max_iterations = 1234;
  s.mapping.extractor.p_gt = 0.55;
  const std::string text = s.to_yaml_text();
  const Settings back = Settings::load_string(text, "saved", ".", robot);
  EXPECT_EQ(back.to_yaml_text(), text);
  EXPECT_EQ(back.mission.loop.views_per_stop, 7);
  EXPECT_EQ(back.motion.planner.max_iterations, 1234);
  EXPECT_EQ(back.mapping.extractor.p_gt, 0.55);
}

TEST(Settings, BadBundlesAreInputErrors) {
  const RobotConfig robot = default_robot_config();
  EXPECT_THROW(Settings::load_string("mapin: {}\n", "t", ".", robot), InputError);
  EXPECT_THROW(Settings::load_string("mission:\n  loop:\n    views_per_stop: -1\n", "t", ".", robot), InputError);
  EXPECT_THROW(Settings::load_string("mission:\n  lop: {}\n", "t", ".", robot), InputError);
  EXPECT_THROW(Settings::load_string("nbv: no_such_file.yaml\n", "t", ".", robot), InputError);
  EXPECT_THROW(Settings::load(std::filesystem::temp_directory_path().string(), robot), InputError);
  try {
    Settings::load_string("mission:\n  scan:\n    azimuths_deg: [0, 95]\n", "bundle.yaml", ".", robot);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("azimuths_deg"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace canopy::mission
