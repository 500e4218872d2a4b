#pragma once
// Ground truth of a generated world's fruits: what mapping metrics are scored against.

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/types.h"
#include "canopy/world/mesh.h"

namespace canopy::world {

/// One fruit: its instance id (as rendered in instance images), its plant, and its surface
/// sampled uniformly by area.
struct FruitTruth {
  int instance_id = 0;
  int plant_index = 0;
  std::string color;                ///< "red", "yellow", "green", ...
  std::string shape;                ///< "blocky" or "conical"
  bool target = true;               ///< Ripe: counted by the metrics (the paper's ground truth).
  Vec3 center = Vec3::Zero();       ///< Centre of the bounding box [m, world].
  Vec3 bbox_min = Vec3::Zero();     ///< Axis-aligned bounding box [m, world].
  Vec3 bbox_max = Vec3::Zero();
  double surface_area_m2 = 0.0;
  double volume_m3 = 0.0;           ///< Enclosed by the fruit's mesh (0 when unknown).
  std::vector<Vec3> surface_points; ///< World-frame surface samples, about spacing_m apart.
};

/// All fruits of a world.
struct GroundTruth {
  double point_spacing_m = 0.003;
  std::vector<FruitTruth> fruits;

  /// Number of target (ripe) fruits.
  size_t target_count() const;
  /// Total number of surface points over all fruits.
  size_t total_points() const;
  /// Fruits of one plant (by plant index), in instance order.
  std::vector<const FruitTruth*> fruits_of_plant(int plant_index) const;

  /// Writes `<dir>/fruits.json` (per-fruit metadata) and `<dir>/fruit_points.csv`
  /// (instance_id,x,y,z per line), each atomically.
  void save(const std::string& dir) const;
  /// Reads what save() wrote; throws InputError naming the file on malformed content.
  static GroundTruth load(const std::string& dir);
};

/// Points on `mesh` uniformly by area, 1/spacing_m^2 per m^2 (stochastic rounding per
/// triangle), from `seed`: the sampler of every world's fruit ground truth.
std::vector<Vec3> sample_surface_points(const TriMesh& mesh, double spacing_m, std::uint64_t seed);

}  // namespace canopy::world
