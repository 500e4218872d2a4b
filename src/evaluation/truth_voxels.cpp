#include "canopy/evaluation/truth_voxels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "canopy/common/error.h"
#include "canopy/common/radix_sort.h"
#include "canopy/mapping/voxel_key.h"

namespace canopy::evaluation {

std::vector<Vec3> world_occupied_voxels(const world::World& world, double res, double plants_from_x_m,
                                        double plants_to_x_m) {
  if (!(std::isfinite(res) && res > 0.0)) throw InputError("world voxels: resolution must be > 0");
  auto key = [res](const Vec3& p) { return mapping::grid_key(p, res); };
  // The keys of every sample, deduplicated in sorted runs (a plant's at a time, then all):
  // the same set a hash set would collect, at a fraction of its cost for millions of samples.
  std::vector<std::uint64_t> keys, run, scratch;
  const auto sort_unique = [&](std::size_t from) {  // radix sort: a window's millions of keys
    run.assign(keys.begin() + static_cast<std::ptrdiff_t>(from), keys.end());
    radix_sort_u64(run, scratch);
    run.erase(std::unique(run.begin(), run.end()), run.end());
    keys.resize(from);
    keys.insert(keys.end(), run.begin(), run.end());
  };
  const double step = 0.5 * res;  // Samples closer than a voxel: no voxel is skipped.
  for (const auto& plant : world.plants) {
    if (!(plant.base_position.x() >= plants_from_x_m && plant.base_position.x() < plants_to_x_m)) continue;
    const std::size_t plant_start = keys.size();
    for (const auto& part : plant.parts) {
      const auto& v = part.mesh.vertices;
      for (const auto& f : part.mesh.faces) {
        const Vec3 &a = v[static_cast<size_t>(f[0])], &b = v[static_cast<size_t>(f[1])], &c = v[static_cast<size_t>(f[2])];
        const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
        const int n = std::max(1, static_cast<int>(std::ceil(longest / step)));
        std::uint64_t last = 0;
        bool any = false;
        for (int i = 0; i <= n; ++i)
          for (int j = 0; j <= n - i; ++j) {
            const std::uint64_t k = key(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
            if (any && k == last) continue;  // neighbouring samples mostly share a voxel
            keys.push_back(k);
            last = k;
            any = true;
          }
      }
    }
    sort_unique(plant_start);
  }
  sort_unique(0);
  std::vector<Vec3> centres;
  centres.reserve(keys.size());
  // In the keys' order, which is the centres' lexicographic (x, y, z) order: a key packs the cell's
  // x, y and z indices from its high bits down, and a centre's coordinate grows with its index.
  for (std::uint64_t k : keys) centres.push_back(mapping::grid_center(k, res));
  return centres;
}

std::vector<Vec3> world_fruit_centres(const world::World& world) {
  std::vector<Vec3> c;
  for (const auto& f : world.truth.fruits) c.push_back(f.center);
  return c;
}

}  // namespace canopy::evaluation
