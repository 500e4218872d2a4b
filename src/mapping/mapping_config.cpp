#include "canopy/mapping/mapping_config.h"

namespace canopy::mapping {

MappingConfig MappingConfig::from_yaml(YamlReader& y) {
  MappingConfig c;
  YamlReader map = y.child("map");
  c.map = SemanticMapParams::from_yaml(map);
  map.finish();
  YamlReader ex = y.child("extractor");
  c.extractor = perception::ExtractorParams::from_yaml(ex);
  ex.finish();
  return c;
}

YAML::Node MappingConfig::to_yaml() const {
  YAML::Node n;
  n["map"] = map.to_yaml();
  n["extractor"] = extractor.to_yaml();
  return n;
}

}  // namespace canopy::mapping
