#include <gtest/gtest.h>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/nbv/nbv_params.h"

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
  EXPECT_EQ(p.planner.top_k, 1);
}

TEST(NbvParams, YamlRoundTrip) {
  NbvParams p;
  p.cluster.epsilon_m = 0.07;
  p.candidates.sphere.azimuth_count = 12;
  p.rays.dense_grid = 20;
  p.gain.max_dist_m = 0.12;
  p.planner.top_k = 2;
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
