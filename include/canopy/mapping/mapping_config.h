#pragma once
// configs/mapping.yaml: the settings of a mapping run, one section per component.

#include <string>

#include "canopy/mapping/map_params.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::mapping {

/// Sections `map` and `extractor`; absent keys keep their defaults. (The bundle's mapping
/// section also holds `metrics`, the evaluation's settings: mission/settings.h.)
struct MappingConfig {
  SemanticMapParams map;
  perception::ExtractorParams extractor;

  /// Reads those sections of one mapping (the caller rejects unknown keys with finish()).
  static MappingConfig from_yaml(YamlReader& y);
  YAML::Node to_yaml() const;
};

}  // namespace canopy::mapping
