#include <gtest/gtest.h>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/nbv/planners/ours/ours_params.h"
#include "canopy/nbv/planners/planners.h"
#include "canopy/common/warning.h"

using namespace canopy;
using namespace canopy::nbv;

TEST(NbvParams, DefaultsArePapersValues) {
  NbvParams p;
  EXPECT_EQ(p.cluster.min_logodds, 1.0);
  EXPECT_EQ(p.cluster.epsilon_m, 0.05);
  EXPECT_EQ(p.cluster.min_points, 3);
  EXPECT_EQ(p.candidates.sphere.radius_m, 0.4);
  EXPECT_EQ(p.candidates.sphere.polar_count, 5);
  EXPECT_EQ(p.candidates.sphere.azimuth_count, 10);
  EXPECT_EQ(p.candidates.sphere.polar_min_deg, 30.0);
  EXPECT_EQ(p.candidates.sphere.polar_max_deg, 150.0);
  EXPECT_EQ(p.rays.cluster_size_m, 0.1);
  EXPECT_EQ(p.rays.step_m, 0.015);
  EXPECT_EQ(p.rays.dense_grid, 28);
  EXPECT_EQ(p.rays.sparse_grid, 6);
  EXPECT_EQ(p.rays.depth_margin_m, 0.05);
  EXPECT_EQ(p.gain.max_dist_m, 0.1);
  EXPECT_EQ(p.planner<OursParams>().top_k, 1);
}

TEST(NbvParams, YamlRoundTrip) {
  NbvParams p;
  p.cluster.epsilon_m = 0.07;
  p.candidates.sphere.azimuth_count = 12;
  p.rays.dense_grid = 20;
  p.gain.max_dist_m = 0.12;
  p.planner<OursParams>().top_k = 2;
  YAML::Emitter e;
  e << params_to_yaml(p);
  YamlReader y = YamlReader::load_string(e.c_str(), "round trip");
  const NbvParams q = params_from_yaml<NbvParams>(y);
  y.finish();
  EXPECT_EQ(q, p);
}

TEST(NbvParams, ConfigFileEqualsStructDefaults) {
  EXPECT_EQ(load_params<NbvParams>(find_data_file("configs/nbv.yaml")), NbvParams{});
}

TEST(NbvParams, BadValuesNameTheKey) {
  YamlReader y = YamlReader::load_string("candidates:\n  radius_m: -1\n", "test.yaml");
  try {
    params_from_yaml<NbvParams>(y);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("radius_m"), std::string::npos);
  }
  YamlReader z = YamlReader::load_string("rays:\n  dense_gird: 3\n", "test.yaml");
  EXPECT_THROW(params_from_yaml<NbvParams>(z), InputError);
}

// Each built-in planner's parameters are the section nbv.<name>, carried by its registry entry
// (no list of planners in nbv_params.h), in the table's order, after the shared sections.
TEST(NbvParams, EachPlannersSectionComesFromItsRegistryEntry) {
  const NbvParams p;
  std::vector<std::string> want, keys;
  for (const ViewPlannerEntry& e : builtin_view_planners())
    if (!e.params.params.empty()) want.push_back(e.name);
  for (const PlannerSection& s : p.planners) {
    keys.push_back(s.key);
    EXPECT_FALSE(s.help.empty()) << s.key;
  }
  EXPECT_EQ(keys, want);
  EXPECT_GE(keys.size(), 6u);  // ours, frontier, predefined, global, reveal, shape
  const YAML::Node y = params_to_yaml(p);
  std::vector<std::string> top;
  for (const auto& kv : y) top.push_back(kv.first.as<std::string>());
  std::vector<std::string> expected = {"cluster", "candidates", "rays", "gain", "views"};
  expected.insert(expected.end(), want.begin(), want.end());
  EXPECT_EQ(top, expected);
  // A planner's parameters are found by their type, and a copy of the settings holds its own.
  NbvParams q = p;
  q.planner<OursParams>().top_k = 4;
  EXPECT_EQ(p.planner<OursParams>().top_k, 1);
  EXPECT_FALSE(q == p);
}

// ours' section was nbv.planner: that key is still read, as nbv.ours, with one warning.
TEST(NbvParams, OursFormerKeyPlannerIsReadWithAWarning) {
  std::vector<std::string> warnings;
  const auto previous = set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
  YamlReader y = YamlReader::load_string("planner:\n  top_k: 3\n", "old_nbv.yaml");
  const NbvParams p = params_from_yaml<NbvParams>(y);
  EXPECT_NO_THROW(y.finish());
  EXPECT_EQ(p.planner<OursParams>().top_k, 3);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("old_nbv.yaml: key 'planner' is now 'ours'"), std::string::npos) << warnings[0];
  YamlReader both = YamlReader::load_string("planner:\n  top_k: 3\nours:\n  top_k: 2\n", "both.yaml");
  EXPECT_THROW(params_from_yaml<NbvParams>(both), InputError);
  set_warning_handler(previous);
}
