#pragma once
// The ground truth as voxels and points, for what may read it: counting the robot's contacts
// with the true plants, `canopy reach` and the motion benchmarks. The planning libraries never
// see it; they plan against the map.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <vector>

#include "canopy/common/types.h"
#include "canopy/world/world.h"

namespace canopy::evaluation {

/// Centres of the voxels (edge `resolution_m`, centres at (k + 1/2) * resolution) that the
/// surfaces of every plant part of `world` pass through: ground-truth occupancy, sorted.
/// Only the plants whose base x lies in [plants_from_x_m, plants_to_x_m) (a long row's window
/// of plants, sim::Simulator::plant_window_x); unbounded, every plant.
std::vector<Vec3> world_occupied_voxels(const world::World& world, double resolution_m,
                                        double plants_from_x_m = -std::numeric_limits<double>::infinity(),
                                        double plants_to_x_m = std::numeric_limits<double>::infinity());

/// The keys (mapping::grid_key, sorted, each once) of the voxels of edge `resolution_m` that
/// samples of `plant`'s surfaces fall in (samples closer than half a voxel, so no voxel is
/// skipped): the plant's part of world_occupied_voxels. `vectorised`: four samples at a time in
/// AVX2 lanes when the processor has them, their keys set in a bit grid over the plant's box;
/// else the reference, every sample's key sorted. The same keys: tests compare both.
std::vector<std::uint64_t> plant_surface_keys(const world::Plant& plant, double resolution_m, bool vectorised = true);

/// world_occupied_voxels of the windows of a long row (issue 49: the mission's truth voxels per
/// rendered window), which overlap: each plant's voxels are kept from the last two windows asked,
/// so a window samples the surfaces of its new plants only. The same voxels, in the same order,
/// as world_occupied_voxels with the same arguments; an unbounded window keeps nothing. Any
/// thread (one asks at a time).
class WindowVoxels {
 public:
  WindowVoxels(const world::World& world, double resolution_m);
  std::vector<Vec3> voxels(double plants_from_x_m, double plants_to_x_m);
  /// Plants whose voxels are held (at most those of the last two windows asked).
  std::size_t plants_held() const;

 private:
  using Keys = std::vector<std::uint64_t>;
  const world::World& world_;
  double resolution_m_;
  mutable std::mutex mutex_;
  std::map<std::size_t, Keys> last_, before_;  // plant index -> its voxels' keys, sorted
};

/// Fruit centres of `world` (ground truth), in instance order.
std::vector<Vec3> world_fruit_centres(const world::World& world);

}  // namespace canopy::evaluation
