#pragma once
// Parameters of the semantic octree and of scan insertion. Defaults are the paper's Table I
// and docs/background/semantic_map.md; configs/mapping.yaml (section `map`) repeats them.

#include <yaml-cpp/yaml.h>

#include <string>

#include "canopy/common/params.h"
#include "canopy/mapping/semantic_state.h"

namespace canopy::mapping {

/// Semantic octree and insertion settings.
struct SemanticMapParams {
  double resolution_m = 0.015;
  float hit_logodds = 1.0f;
  float pass_logodds = -0.1f;
  float clamp_min_logodds = -9.21f;
  float clamp_max_logodds = 9.21f;
  double max_range_m = 1.0;
  double ray_range_m = 0.8;
  float unseen_logodds = -0.1f;
  bool prune = true;
  EntropyCategories entropy_categories = EntropyCategories::kPaper;
  int threads = 0;

  UpdateRule rule() const { return {hit_logodds, pass_logodds, clamp_min_logodds, clamp_max_logodds}; }

  template <class A>
  void visit(A& a) {
    a("resolution_m", resolution_m, limits::in(0.001, 1.0), "Voxel edge, delta S [m]");
    a("hit_logodds", hit_logodds, limits::positive(), "psi: log-odds added to the observed class on a hit");
    a("pass_logodds", pass_logodds, limits::negative(), "phi: log-odds added to every stored class on a pass");
    a("clamp_min_logodds", clamp_min_logodds, limits::negative(), "Lower log-odds clamp");
    a("clamp_max_logodds", clamp_max_logodds, limits::positive(), "Upper log-odds clamp");
    a("max_range_m", max_range_m, limits::positive(), "Endpoints farther than this are not hits [m]");
    a("ray_range_m", ray_range_m, limits::positive(), "Free space is carved up to this distance [m]");
    a("unseen_logodds", unseen_logodds, limits::finite(), "SSMI's prior chi of never-observed voxels (entropy)");
    a("prune", prune, "Collapse eight identical children after each scan");
    a.choice("entropy_categories", entropy_categories, kEntropyCategoriesNames,
             "What the multi-class entropy H(x) runs over (gains and the paper rule's metrics)");
    a("threads", threads, limits::in(0, 256), "Worker threads for insertion; 0 = all cores");
    a.check(unseen_logodds >= clamp_min_logodds && unseen_logodds <= clamp_max_logodds, "unseen_logodds",
            "must lie within [clamp_min_logodds, clamp_max_logodds]");
    a.check(hit_logodds < clamp_max_logodds, "hit_logodds", "must be below clamp_max_logodds");
    a.check(pass_logodds > clamp_min_logodds, "pass_logodds", "must be above clamp_min_logodds");
  }
  /// Throws InputError naming `where` when a value is out of range.
  void validate(const std::string& where) const { validate_params(*this, where); }
  bool operator==(const SemanticMapParams& o) const { return same_params(*this, o); }
};

}  // namespace canopy::mapping
