#include <gtest/gtest.h>

#include <fstream>

#include "canopy/robot/robot_config.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/map_params.h"
#include "canopy/perception/semantic_extractor.h"

using namespace canopy;

namespace {
template <typename P>
P round_trip(const P& p) {
  YAML::Emitter e;
  e << params_to_yaml(p);
  YamlReader y = YamlReader::load_string(e.c_str(), "round trip");
  P q = params_from_yaml<P>(y);
  y.finish();
  return q;
}
}  // namespace

TEST(MappingParams, DefaultsArePapersValues) {
  mapping::SemanticMapParams p;
  EXPECT_EQ(p.resolution_m, 0.015);
  EXPECT_EQ(p.hit_logodds, 1.0f);
  EXPECT_EQ(p.pass_logodds, -0.1f);
  EXPECT_EQ(p.clamp_max_logodds, 9.21f);
  EXPECT_EQ(p.clamp_min_logodds, -9.21f);
  EXPECT_EQ(p.max_range_m, 1.0);
  EXPECT_EQ(p.ray_range_m, 0.8);
  perception::ExtractorParams e;
  EXPECT_EQ(e.p_gt, 0.7);
  evaluation::MetricsParams m;
  EXPECT_EQ(m.coverage_distance_m, 0.015);
  EXPECT_EQ(m.entropy_box_m, 0.1);
}

TEST(MappingParams, YamlRoundTrip) {
  mapping::SemanticMapParams p;
  p.resolution_m = 0.02;
  p.hit_logodds = 0.85f;
  p.pass_logodds = -0.4f;
  p.threads = 2;
  EXPECT_EQ(round_trip(p), p);
  perception::ExtractorParams e;
  e.source = perception::LabelSource::kTruth;
  e.p_gt = 0.9;
  e.color.bands.pop_back();
  EXPECT_EQ(round_trip(e), e);
  evaluation::MetricsParams m;
  m.entropy_box_m = 0.12;
  EXPECT_EQ(round_trip(m), m);
}

// configs/mapping.yaml restates the defaults.
TEST(MappingParams, ConfigFileEqualsStructDefaults) {
  YamlReader y = YamlReader::load_file(find_data_file("configs/mapping.yaml"));
  YamlReader map = y.child("map");
  EXPECT_EQ(params_from_yaml<mapping::SemanticMapParams>(map), mapping::SemanticMapParams{});
  map.finish();
  YamlReader ex = y.child("extractor");
  EXPECT_EQ(params_from_yaml<perception::ExtractorParams>(ex), perception::ExtractorParams{});
  ex.finish();
  YamlReader me = y.child("metrics");
  EXPECT_EQ(params_from_yaml<evaluation::MetricsParams>(me), evaluation::MetricsParams{});
  me.finish();
  y.finish();
}

TEST(MappingParams, UnknownAndBadKeysAreErrors) {
  YamlReader y = YamlReader::load_string("resolution_m: 0.01\nresolutoin: 3\n", "t.yaml");
  params_from_yaml<mapping::SemanticMapParams>(y);
  EXPECT_THROW(y.finish(), InputError);
  // A float out of range names the file, the key and the value; a cross-field check too.
  YamlReader clamp = YamlReader::load_string("hit_logodds: 12\n", "c.yaml");
  try {
    params_from_yaml<mapping::SemanticMapParams>(clamp);
    FAIL() << "hit_logodds above the clamp was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "c.yaml: key 'hit_logodds': value '12' must be below clamp_max_logodds");
  }
  YamlReader bad = YamlReader::load_string("pass_logodds: 0.5\n", "t.yaml");
  EXPECT_THROW(params_from_yaml<mapping::SemanticMapParams>(bad), InputError);
  YamlReader bad2 = YamlReader::load_string("p_gt: 1.5\n", "t.yaml");
  EXPECT_THROW(params_from_yaml<perception::ExtractorParams>(bad2), InputError);
  YamlReader bad3 = YamlReader::load_string("source: magic\n", "t.yaml");
  EXPECT_THROW(params_from_yaml<perception::ExtractorParams>(bad3), InputError);
}
