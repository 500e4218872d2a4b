#include "canopy/evaluation/truth_voxels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <queue>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/common/radix_sort.h"
#include "canopy/mapping/voxel_key.h"

namespace canopy::evaluation {

namespace {

void check_resolution(double res) {
  if (!(std::isfinite(res) && res > 0.0)) throw InputError("world voxels: resolution must be > 0");
}

bool in_window(const world::World& world, std::size_t p, double from_x_m, double to_x_m) {
  const Vec3& base = world.plants[p].base_position;
  return base.x() >= from_x_m && base.x() < to_x_m;
}

// The keys (sorted, each once) of every sample of a plant's surfaces, samples closer than a
// voxel so that no voxel is skipped. Radix-sorted: a plant's hundreds of thousands of keys.
std::vector<std::uint64_t> plant_keys(const world::Plant& plant, double res, std::vector<std::uint64_t>* scratch) {
  auto key = [res](const Vec3& p) { return mapping::grid_key(p, res); };
  std::vector<std::uint64_t> keys;
  const double step = 0.5 * res;
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
  radix_sort_u64(keys, *scratch);
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  keys.shrink_to_fit();  // kept per plant (WindowVoxels): the samples were several times more
  return keys;
}

// The plants' sorted keys merged (each key once) straight into voxel centres, without a copy of
// them all: in the keys' order, which is the centres' lexicographic (x, y, z) order (a key packs
// the cell's x, y and z indices from its high bits down, and a centre's coordinate grows with
// its index).
std::vector<Vec3> centres_of(const std::map<std::size_t, std::vector<std::uint64_t>>& runs, double res) {
  using Run = std::vector<std::uint64_t>;
  using Head = std::pair<std::uint64_t, std::pair<const Run*, std::size_t>>;  // key, (run, next index)
  std::priority_queue<Head, std::vector<Head>, std::greater<Head>> heads;
  std::size_t total = 0;
  for (const auto& [p, keys] : runs) {
    total += keys.size();
    if (!keys.empty()) heads.push({keys[0], {&keys, 1}});
  }
  std::vector<Vec3> centres;
  centres.reserve(total);
  bool any = false;
  std::uint64_t previous = 0;
  while (!heads.empty()) {
    const auto [key, run] = heads.top();
    heads.pop();
    if (!any || key != previous) centres.push_back(mapping::grid_center(key, res));
    any = true;
    previous = key;
    if (run.second < run.first->size()) heads.push({(*run.first)[run.second], {run.first, run.second + 1}});
  }
  centres.shrink_to_fit();
  return centres;
}

}  // namespace

std::vector<Vec3> world_occupied_voxels(const world::World& world, double res, double plants_from_x_m,
                                        double plants_to_x_m) {
  check_resolution(res);
  std::map<std::size_t, std::vector<std::uint64_t>> keys;
  std::vector<std::uint64_t> scratch;
  for (std::size_t p = 0; p < world.plants.size(); ++p)
    if (in_window(world, p, plants_from_x_m, plants_to_x_m))
      keys.emplace(p, plant_keys(*world.plant(p), res, &scratch));  // generated again when not held
  return centres_of(keys, res);
}

WindowVoxels::WindowVoxels(const world::World& world, double resolution_m) : world_(world), resolution_m_(resolution_m) {
  check_resolution(resolution_m);
}

std::vector<Vec3> WindowVoxels::voxels(double plants_from_x_m, double plants_to_x_m) {
  // Unbounded: every plant, once (a world built whole), nothing kept.
  if (!(std::isfinite(plants_from_x_m) && std::isfinite(plants_to_x_m)))
    return world_occupied_voxels(world_, resolution_m_, plants_from_x_m, plants_to_x_m);
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::size_t, Keys> now;
  std::vector<std::uint64_t> scratch;
  for (std::size_t p = 0; p < world_.plants.size(); ++p) {
    if (!in_window(world_, p, plants_from_x_m, plants_to_x_m)) continue;
    auto held = last_.extract(p);  // moved, not copied: the windows' keys are held once
    if (held.empty()) held = before_.extract(p);
    if (held.empty()) {
      now.emplace(p, plant_keys(*world_.plant(p), resolution_m_, &scratch));  // generated again when not held
    } else {
      now.insert(std::move(held));
    }
  }
  std::vector<std::uint64_t>().swap(scratch);
  before_ = std::move(last_);
  last_ = std::move(now);
  return centres_of(last_, resolution_m_);
}

std::size_t WindowVoxels::plants_held() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t n = last_.size();
  for (const auto& [p, keys] : before_) n += !last_.count(p);
  return n;
}

std::vector<Vec3> world_fruit_centres(const world::World& world) {
  std::vector<Vec3> c;
  for (const auto& f : world.truth.fruits) c.push_back(f.center);
  return c;
}

}  // namespace canopy::evaluation
