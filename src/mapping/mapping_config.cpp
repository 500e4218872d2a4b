#include "canopy/mapping/mapping_config.h"

namespace canopy::mapping {

MappingConfig MappingConfig::load(const std::string& path) {
  YamlReader y = YamlReader::load_file(path);
  return from_yaml(y);
}

MappingConfig MappingConfig::from_yaml(YamlReader& y) {
  MappingConfig c;
  YamlReader map = y.child("map");
  c.map = SemanticMapParams::from_yaml(map);
  map.finish();
  YamlReader ex = y.child("extractor");
  c.extractor = perception::ExtractorParams::from_yaml(ex);
  ex.finish();
  YamlReader me = y.child("metrics");
  c.metrics = MetricsParams::from_yaml(me);
  me.finish();
  y.finish();
  return c;
}

YAML::Node MappingConfig::to_yaml() const {
  YAML::Node n;
  n["map"] = map.to_yaml();
  n["extractor"] = extractor.to_yaml();
  n["metrics"] = metrics.to_yaml();
  return n;
}

}  // namespace canopy::mapping
