#pragma once
// Parameters of the semantic octree and of scan insertion. Defaults are the paper's Table I
// and docs/background/semantic_map.md; configs/mapping.yaml (section `map`) repeats them.

#include <yaml-cpp/yaml.h>

#include <string>

#include "canopy/common/params.h"
#include "canopy/mapping/semantic_state.h"

namespace canopy::mapping {

/// How many SSMI hit updates a scan gives a voxel.
///  - kPerVoxel: the cloud is voxel-filtered on the map's own grid: one hit per voxel per scan,
///    with the majority label (OctoMap's discretised insertion).
///  - kPerEndpoint: the cloud is voxel-filtered at the map resolution on a grid of the camera's
///    axes with its corner at the camera (a filter run on the camera-frame cloud, as a PCL
///    voxel grid would); each remaining point (a cell's centroid, with the cell's majority
///    label) is one hit update of the map voxel it falls in, so a voxel that the filter's
///    cells overlap can get several hits from one scan.
enum class Insertion { kPerVoxel, kPerEndpoint };
inline constexpr EnumName<Insertion> kInsertionNames[] = {{Insertion::kPerVoxel, "per_voxel"},
                                                          {Insertion::kPerEndpoint, "per_endpoint"}};

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
  Insertion insertion = Insertion::kPerVoxel;
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
    a.choice("insertion", insertion, kInsertionNames,
             "Hits per scan: one per map voxel (per_voxel) or one per point left by a camera-frame voxel filter (per_endpoint)");
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
