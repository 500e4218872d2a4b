#pragma once
// configs/mapping.yaml: the settings of a mapping run, one section per component.

#include <string>

#include "canopy/mapping/map_metrics.h"
#include "canopy/mapping/map_params.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::mapping {

/// Sections `map`, `extractor` and `metrics`; absent keys keep their defaults.
struct MappingConfig {
  SemanticMapParams map;
  perception::ExtractorParams extractor;
  MetricsParams metrics;

  /// Reads a config file; throws InputError naming the file and key (unknown keys too).
  static MappingConfig load(const std::string& path);
  /// Reads one mapping with those sections (unknown keys rejected).
  static MappingConfig from_yaml(YamlReader& y);
  YAML::Node to_yaml() const;
};

}  // namespace canopy::mapping
