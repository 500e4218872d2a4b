#pragma once
// Parameters of the semantic octree and of scan insertion. Defaults are the paper's Table I
// and docs/background/semantic_map.md; configs/mapping.yaml (section `map`) repeats them.

#include <yaml-cpp/yaml.h>

#include <string>

#include "canopy/common/yaml_reader.h"
#include "canopy/mapping/semantic_state.h"

namespace canopy::mapping {

/// Semantic octree and insertion settings.
struct SemanticMapParams {
  double resolution_m = 0.015;       ///< Voxel edge (delta S).
  float hit_logodds = 1.0f;          ///< psi.
  float pass_logodds = -0.1f;        ///< phi.
  float clamp_min_logodds = -9.21f;  ///< Lower log-odds clamp.
  float clamp_max_logodds = 9.21f;   ///< Upper log-odds clamp.
  double max_range_m = 1.0;          ///< Endpoints farther than this are not hits.
  double ray_range_m = 0.8;          ///< Free space is carved up to this distance.
  float unseen_logodds = -0.1f;      ///< SSMI's prior chi for never-observed voxels (entropy).
  bool prune = true;                 ///< Collapse eight identical children after each scan.
  /// What H(x) runs over (semantic_state.h): the NBV gains' entropy and the metrics' paper rule.
  EntropyCategories entropy_categories = EntropyCategories::kPaper;
  int threads = 0;                   ///< Worker threads for insertion; 0 = all cores.

  UpdateRule rule() const { return {hit_logodds, pass_logodds, clamp_min_logodds, clamp_max_logodds}; }

  /// Reads the keys of one YAML mapping (unknown keys are errors after finish()).
  static SemanticMapParams from_yaml(YamlReader& y);
  /// The same keys as a YAML mapping (round-trips through from_yaml exactly).
  YAML::Node to_yaml() const;
  /// Throws InputError naming `where` when a value is out of range.
  void validate(const std::string& where) const;
  bool operator==(const SemanticMapParams& o) const;
};

}  // namespace canopy::mapping
