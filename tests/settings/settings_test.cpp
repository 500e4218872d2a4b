// The settings bundle: defaults equal the shipped configs, a saved bundle loads back to the
// same settings, and bad bundles are input errors.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/data_dir.h"
#include "canopy/common/read_file.h"
#include "canopy/common/warning.h"
#include "canopy/nbv/planners/frontier/frontier_params.h"
#include "canopy/nbv/planners/ours/ours_params.h"
#include "canopy/nbv/planners/planners.h"
#include "canopy/settings/settings.h"

namespace canopy::settings {
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
  s.nbv.planner<nbv::FrontierParams>().max_targets = 42;
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

// Issue 31, item 2: an empty key path crashed (YAML::Node::operator[] on no key).
TEST(Settings, EmptyOrDanglingKeyPathsAreInputErrors) {
  Settings s = Settings::defaults(default_robot_config());
  for (const char* key : {"", ".", "mission.loop.", ".mission"}) {
    try {
      s.set(key, "1", "--set");
      ADD_FAILURE() << "key '" << key << "' was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--set: "), std::string::npos) << e.what();
    }
  }
}

// Any setting is named by its key path; the value is validated like the file's.
TEST(Settings, SetNamesAnySettingByItsKeyPath) {
  const RobotConfig robot = default_robot_config();
  Settings s = Settings::defaults(robot);
  s.set("mission.loop.views_per_stop", "6", "--set");
  s.set("nbv.gain.proximity", "per_voxel", "--set");
  s.set("method.name", "frontier", "--method");
  s.set("mapping.map.pass_logodds", "-0.4", "--set");
  s.set("mission.scan.heights_m", "[0.5, 0.9]", "--set");
  EXPECT_EQ(s.mission.loop.views_per_stop, 6);
  EXPECT_EQ(s.nbv.gain.proximity, nbv::Proximity::kPerVoxel);
  EXPECT_EQ(s.method.name, "frontier");
  EXPECT_EQ(s.mapping.map.pass_logodds, -0.4f);
  EXPECT_EQ(s.mission.scan.heights_m, (std::vector<double>{0.5, 0.9}));
  auto error = [&](const std::string& key, const std::string& value) {
    Settings t = s;
    try {
      t.set(key, value, "--set " + key + "=" + value);
    } catch (const InputError& e) {
      EXPECT_EQ(t.to_yaml_text(), s.to_yaml_text()) << "a failed set changed the settings";
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error("mission.loop.views_per_stp", "6"),
            "--set mission.loop.views_per_stp=6: unknown setting 'mission.loop.views_per_stp' (settings are named by "
            "key paths such as mission.loop.views_per_stop)");
  EXPECT_EQ(error("mission.loop.views_per_stop", "-2"),
            "--set mission.loop.views_per_stop=-2: key 'mission.loop.views_per_stop': value '-2' must be in [0, 10000]");
  std::string names;
  for (const nbv::ViewPlannerEntry& e : nbv::builtin_view_planners()) names += (names.empty() ? "" : ", ") + e.name;
  EXPECT_EQ(error("method.name", "magic"),
            "--set method.name=magic: key 'method.name': value 'magic' must be one of: " + names);
  EXPECT_NE(error("nbv", "3").find("must be a mapping"), std::string::npos);
  EXPECT_NE(error("nbv.gain.proximity", "[unclosed").find("is not valid YAML"), std::string::npos);
  EXPECT_EQ(parse_override("a.b=c d", "--set"), (SettingOverride{"a.b", "c d"}));
  EXPECT_THROW(parse_override("a.b", "--set"), InputError);
  EXPECT_THROW(parse_override("=3", "--set"), InputError);
}

// The reference of every setting: each key once, with its value, limits and help.
TEST(Settings, DescribeCoversEveryKeyOnce) {
  const Settings s = Settings::defaults(default_robot_config());
  const std::vector<ParamDescription> d = s.describe();
  std::set<std::string> keys;
  for (const ParamDescription& p : d) {
    EXPECT_TRUE(keys.insert(p.key).second) << p.key << " twice";
    EXPECT_FALSE(p.help.empty()) << p.key << " has no help";
  }
  EXPECT_GT(d.size(), 100u);
  EXPECT_TRUE(keys.count("method.name"));
  EXPECT_TRUE(keys.count("nbv.candidates.radius_m"));  // the view sphere's keys, inline
  EXPECT_TRUE(keys.count("mapping.metrics.rule"));
  EXPECT_TRUE(keys.count("motion.planner.max_iterations"));
  // Every described key can be set to its own value.
  Settings t = s;
  for (const ParamDescription& p : d) {
    if (p.limits != "a list") {
      EXPECT_NO_THROW(t.set(p.key, p.value, p.key)) << p.key << " = " << p.value;
    }
  }
  EXPECT_EQ(t.to_yaml_text(), s.to_yaml_text());
}

// configs/canopy.yaml and configs/nbv.yaml are what the structs write (YamlDoc): regenerate them
// with `canopy settings --file NAME > configs/NAME.yaml`.
TEST(Settings, ShippedFilesAreWhatTheStructsWrite) {
  for (const std::string& name : generated_settings_files()) {
    SCOPED_TRACE(name);
    EXPECT_EQ(read_file(find_data_file("configs/" + name + ".yaml")), settings_file_text(name, "test"))
        << "configs/" << name << ".yaml is out of date: canopy settings --file " << name << " > configs/" << name
        << ".yaml";
  }
  EXPECT_THROW(settings_file_text("mapping", "--file"), InputError);
  // Every view planner's name is in the bundle's comment (the registry's names, not a list by hand).
  const std::string bundle = settings_file_text("canopy", "test");
  for (const nbv::ViewPlannerEntry& e : nbv::builtin_view_planners())
    EXPECT_NE(bundle.find(e.name), std::string::npos) << e.name;
}

// ours' section is nbv.ours; --set and experiment files naming nbv.planner still work, with a
// warning, and a saved bundle says nbv.ours.
TEST(Settings, OursFormerSectionIsSetWithAWarning) {
  std::vector<std::string> warnings;
  const auto previous = set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
  Settings s = Settings::defaults(default_robot_config());
  s.set("nbv.planner.top_k", "3", "--set");
  EXPECT_EQ(s.nbv.planner<nbv::OursParams>().top_k, 3);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "--set: key 'nbv.planner' is now 'nbv.ours'; read as such (rename it: the old name will be refused)");
  const std::string text = s.to_yaml_text();
  EXPECT_NE(text.find("  ours:\n    top_k: 3\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("  planner:\n    top_k"), std::string::npos) << text;
  const Settings old = Settings::load_string("nbv:\n  planner:\n    top_k: 2\n", "old.yaml", ".", default_robot_config());
  EXPECT_EQ(old.nbv.planner<nbv::OursParams>().top_k, 2);
  EXPECT_EQ(warnings.size(), 2u);
  set_warning_handler(previous);
}

}  // namespace
}  // namespace canopy::settings
