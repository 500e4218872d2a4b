#include "canopy/nbv/voxel_index.h"

#include "canopy/common/timer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/mapping/voxel_key.h"
#include "canopy/mapping/voxel_ray.h"

namespace canopy::nbv {

namespace {

constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

inline std::uint64_t hash64(std::uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  return x ^ (x >> 33);
}

double binary_entropy(double p) {
  if (p <= 0.0 || p >= 1.0) return 0.0;
  return -p * std::log(p) - (1.0 - p) * std::log(1.0 - p);
}

// KL(q || p) where q_j is proportional to p_j e^{delta_j}: sum_j q_j delta_j - ln sum_j p_j e^{delta_j}.
double update_kl(const double* p, const double* delta, int n) {
  double z = 0.0;
  for (int j = 0; j < n; ++j) z += p[j] * std::exp(delta[j]);
  if (!(z > 0.0)) return 0.0;
  double s = 0.0;
  for (int j = 0; j < n; ++j) s += p[j] * std::exp(delta[j]) / z * delta[j];
  return std::max(0.0, s - std::log(z));
}

}  // namespace

VoxelInfo make_voxel_info(const mapping::SemanticOcTree& map, const mapping::SemanticState* state) {
  VoxelInfo v;
  const int K = map.num_classes();
  CANOPY_CHECK(K + 1 <= VoxelInfo::kMaxCategories, "VoxelInfo holds at most " << VoxelInfo::kMaxCategories - 1
                                                                              << " classes, the map has " << K);
  // MI treats an unknown voxel as a fresh leaf (p_occ = 0.5, classes equally likely): the state
  // a voxel has before its first update.
  const mapping::SemanticState fresh{};
  const mapping::SemanticState& s = state ? *state : fresh;
  v.known = state != nullptr;
  if (state) {
    v.p_occ = float(s.occupancy());
    v.entropy = float(map.entropy_of(s));
    v.binary_entropy = float(binary_entropy(s.occupancy()));
    v.cls = static_cast<std::int8_t>(s.most_likely_class());
    v.is_target = mapping::SemanticOcTree::is_class_voxel(s, map.classes().target_index());
  } else {
    v.p_occ = 0.5f;
    v.entropy = float(map.unseen_entropy());
    v.binary_entropy = float(std::log(2.0));
  }
  double p[VoxelInfo::kMaxCategories] = {};
  s.distribution(K, p);
  for (int j = 0; j <= K; ++j) v.prob[j] = float(p[j]);
  const mapping::UpdateRule rule = map.rule();
  double delta[VoxelInfo::kMaxCategories] = {};
  for (int j = 1; j <= K; ++j) delta[j] = rule.pass;
  v.kl_free = float(update_kl(p, delta, K + 1));
  for (int k = 0; k < K; ++k) {
    delta[k + 1] = rule.hit;
    v.kl_hit[k] = float(update_kl(p, delta, K + 1));
    delta[k + 1] = rule.pass;
  }
  return v;
}

void VoxelIndex::grow() { rehash(table_keys_.empty() ? 1024 : table_keys_.size() * 2); }

void VoxelIndex::rehash(std::size_t cap) {
  table_keys_.assign(cap, kEmpty);
  table_values_.assign(cap, 0);
  table_mask_ = cap - 1;
  table_shift_ = 64;
  for (std::size_t c = cap; c > 1; c >>= 1) --table_shift_;
  for (std::size_t i = 0; i < brick_keys_.size(); ++i) {
    std::uint64_t h = slot(brick_keys_[i]);
    while (table_keys_[h] != kEmpty) h = (h + 1) & table_mask_;
    table_keys_[h] = brick_keys_[i];
    table_values_[h] = static_cast<std::uint32_t>(i);
  }
}

std::uint32_t* VoxelIndex::brick_for_insert(std::uint64_t bk) {
  if ((brick_keys_.size() + 1) * 2 > table_keys_.size()) grow();
  std::uint64_t h = slot(bk);
  while (table_keys_[h] != kEmpty) {
    if (table_keys_[h] == bk) return &cells_[std::size_t(table_values_[h]) * kBrickCells];
    h = (h + 1) & table_mask_;
  }
  table_keys_[h] = bk;
  table_values_[h] = static_cast<std::uint32_t>(brick_keys_.size());
  brick_keys_.push_back(bk);
  brick_stamps_.push_back(generation_);  // all unknown: as when it was absent
  cells_.resize(cells_.size() + kBrickCells, 0u);
  return &cells_[cells_.size() - kBrickCells];
}

const std::uint32_t* VoxelIndex::brick(std::uint64_t bk) const {
  if (table_keys_.empty()) return nullptr;
  std::uint64_t h = slot(bk);
  for (;;) {
    const std::uint64_t k = table_keys_[h];
    if (k == bk) return &cells_[std::size_t(table_values_[h]) * kBrickCells];
    if (k == kEmpty) return nullptr;
    h = (h + 1) & table_mask_;
  }
}

void VoxelIndex::rebuild(const mapping::SemanticOcTree& map) {
  const Stopwatch watch;
  map_ = &map;
  revision_ = map.revision();
  resolution_ = map.getResolution();
  palette_.clear();
  palette_.push_back(make_voxel_info(map, nullptr));
  cells_.clear();
  brick_keys_.clear();
  brick_stamps_.clear();
  rebuilt_at_ = ++generation_;
  table_keys_.clear();
  table_values_.clear();
  grow();

  ids_.clear();
  ids_.reserve(1024);
  dropped_stamps_.clear();  // every brick unchanged since this rebuild
  // Every state is interned, the dropped bricks' too (keep_x(): their voxels are read from the
  // map and answered by their states' ids), and those of the map's moved-out subtrees (the
  // map's keep_x(): read again when it puts them back).
  map.for_each_leaf_all([&](const octomap::OcTreeKey& key, unsigned depth, const mapping::SemanticState& state) {
    const std::uint32_t id = intern(map, state);
    const unsigned side = 1u << (16 - depth);
    if (side == 1) {
      if (!dropped_x(unsigned(key[0]) >> kBrickBits))
        brick_for_insert(mapping::brick_key(key))[mapping::brick_cell(key[0], key[1], key[2])] = id;
      return;
    }
    unsigned lo[3], hi[3];  // voxel key range [lo, hi]
    for (int i = 0; i < 3; ++i) {
      lo[i] = unsigned(key[i]) - side / 2;
      hi[i] = lo[i] + side - 1;
    }
    // Fill brick by brick.
    for (unsigned bz = lo[2] >> kBrickBits; bz <= hi[2] >> kBrickBits; ++bz)
      for (unsigned by = lo[1] >> kBrickBits; by <= hi[1] >> kBrickBits; ++by)
        for (unsigned bx = lo[0] >> kBrickBits; bx <= hi[0] >> kBrickBits; ++bx) {
          if (dropped_x(bx)) continue;
          const std::uint64_t bk = mapping::brick_key_of_brick(bx, by, bz);
          std::uint32_t* cells = brick_for_insert(bk);
          const unsigned x0 = std::max(lo[0], bx << kBrickBits), x1 = std::min(hi[0], (bx << kBrickBits) + kBrickSide - 1);
          const unsigned y0 = std::max(lo[1], by << kBrickBits), y1 = std::min(hi[1], (by << kBrickBits) + kBrickSide - 1);
          const unsigned z0 = std::max(lo[2], bz << kBrickBits), z1 = std::min(hi[2], (bz << kBrickBits) + kBrickSide - 1);
          for (unsigned z = z0; z <= z1; ++z)
            for (unsigned y = y0; y <= y1; ++y)
              for (unsigned x = x0; x <= x1; ++x) cells[mapping::brick_cell(x, y, z)] = id;
        }
  });
  build_ms_ = watch.ms();
}

std::uint32_t VoxelIndex::intern(const mapping::SemanticOcTree& map, const mapping::SemanticState& state) {
  const detail::StateBytes sb(state);
  const auto it = ids_.find(sb);
  if (it != ids_.end()) return it->second;
  const auto id = static_cast<std::uint32_t>(palette_.size());
  palette_.push_back(make_voxel_info(map, &state));
  ids_.emplace(sb, id);
  return id;
}

std::size_t detail::StateHash::operator()(const StateBytes& s) const {
  return hash64(s.a ^ hash64(s.b ^ (std::uint64_t(s.c) << 7)));
}

bool VoxelIndex::apply_updates(const mapping::SemanticOcTree& map, std::uint64_t revision_before,
                               const std::vector<mapping::VoxelUpdate>& updates) {
  if (map_ != &map || revision_ != revision_before || resolution_ != map.getResolution()) return false;
  // States that are no longer in the map stay in the palette; past a bound, rebuild instead.
  if (palette_.size() > kMaxPalette) return false;
  const Stopwatch watch;
  // Equal ids are identical states (one palette), so a cell whose id changes is a voxel whose
  // state changed: its brick is stamped (changed_since).
  const std::uint64_t generation = generation_ + 1;
  bool changed = false;
  for (const mapping::VoxelUpdate& u : updates) {
    const octomap::OcTreeKey key = mapping::morton_key(u.code);
    const mapping::SemanticState* s = map.find(key);
    const std::uint32_t id = s ? intern(map, *s) : 0;  // an update leaves a known voxel: s is set
    if (dropped_x(unsigned(key[0]) >> kBrickBits)) {
      // Not held (keep_x()): its state is interned above; whether it changed is not known, so
      // its brick counts as changed.
      dropped_stamps_[mapping::brick_key(key)] = generation;
      changed = true;
      continue;
    }
    std::uint32_t* cells = brick_for_insert(mapping::brick_key(key));
    std::uint32_t& cell = cells[mapping::brick_cell(key[0], key[1], key[2])];
    if (cell == id) continue;
    cell = id;
    brick_stamps_[std::size_t(cells - cells_.data()) / kBrickCells] = generation;
    changed = true;
  }
  if (changed) generation_ = generation;
  revision_ = map.revision();
  update_ms_ += watch.ms();
  return true;
}

bool VoxelIndex::refresh(const mapping::SemanticOcTree& map) {
  if (map_ == &map && revision_ == map.revision()) return false;
  rebuild(map);
  return true;
}

std::uint32_t VoxelIndex::lookup(const octomap::OcTreeKey& key) const {
  const std::uint32_t* b = brick(mapping::brick_key(key));
  if (b) return b[mapping::brick_cell(key[0], key[1], key[2])];
  return dropped_x(unsigned(key[0]) >> kBrickBits) ? map_id(key[0], key[1], key[2]) : 0u;
}

std::uint32_t VoxelIndex::map_id(unsigned x, unsigned y, unsigned z) const {
  const mapping::SemanticState* s = map_->find(octomap::OcTreeKey(static_cast<octomap::key_type>(x),
                                                                  static_cast<octomap::key_type>(y),
                                                                  static_cast<octomap::key_type>(z)));
  if (!s) return 0u;
  const auto it = ids_.find(detail::StateBytes(*s));
  CANOPY_CHECK(it != ids_.end(), "VoxelIndex: a state of the map was never interned");
  return it->second;
}

void VoxelIndex::drop_outside() {
  std::vector<std::uint32_t> cells;
  std::vector<std::uint64_t> keys, stamps;
  for (std::size_t i = 0; i < brick_keys_.size(); ++i) {
    const std::uint64_t bk = brick_keys_[i];
    if (dropped_x(brick_x(bk))) {
      if (brick_stamps_[i] > rebuilt_at_) dropped_stamps_[bk] = brick_stamps_[i];
      continue;
    }
    keys.push_back(bk);
    stamps.push_back(brick_stamps_[i]);
    cells.insert(cells.end(), cells_.begin() + std::ptrdiff_t(i * kBrickCells),
                 cells_.begin() + std::ptrdiff_t((i + 1) * kBrickCells));
  }
  if (keys.size() == brick_keys_.size()) return;
  // New vectors: their capacity is what the window holds, not what the row once held.
  cells_ = std::move(cells);
  brick_keys_ = std::move(keys);
  brick_stamps_ = std::move(stamps);
  std::size_t cap = 1024;
  while ((brick_keys_.size() + 1) * 2 > cap) cap *= 2;
  rehash(cap);
}

void VoxelIndex::admit(const mapping::SemanticOcTree& map, unsigned lo, unsigned hi) {
  const std::size_t before = brick_keys_.size();
  const octomap::OcTreeKey klo(static_cast<octomap::key_type>(lo << kBrickBits), 0, 0),
      khi(static_cast<octomap::key_type>(std::min(0xffffu, (hi << kBrickBits) + kBrickSide - 1)), 0xffff, 0xffff);
  map.for_each_voxel_in_keys_if(
      klo, khi, [](const mapping::SemanticState&) { return true; },
      [&](const octomap::OcTreeKey& key, const mapping::SemanticState& state) {
        const unsigned bx = unsigned(key[0]) >> kBrickBits;
        if (bx < lo || bx > hi) return;  // a pruned block's voxels beyond the stretch
        brick_for_insert(mapping::brick_key(key))[mapping::brick_cell(key[0], key[1], key[2])] = intern(map, state);
      });
  // The bricks come back as they were: their stamps kept when dropped, else unchanged since the rebuild.
  for (std::size_t i = before; i < brick_keys_.size(); ++i) {
    const auto it = dropped_stamps_.find(brick_keys_[i]);
    brick_stamps_[i] = it == dropped_stamps_.end() ? rebuilt_at_ : it->second;
    if (it != dropped_stamps_.end()) dropped_stamps_.erase(it);
  }
}

void VoxelIndex::keep_x(const mapping::SemanticOcTree& map, double x_lo_m, double x_hi_m) {
  CANOPY_CHECK(std::isfinite(x_lo_m) && std::isfinite(x_hi_m) && x_lo_m <= x_hi_m,
               "VoxelIndex::keep_x: [" << x_lo_m << ", " << x_hi_m << "] is not a stretch");
  const double res = map.getResolution();
  auto brick_x_of = [&](double x) {
    const double k = std::clamp(std::floor(x / res) + 32768.0, 0.0, 65535.0);
    return unsigned(k) >> kBrickBits;
  };
  const unsigned lo = brick_x_of(x_lo_m), hi = brick_x_of(x_hi_m);
  const bool current = map_ == &map && revision_ == map.revision() && resolution_ == res;
  const bool was = windowed_;
  const unsigned old_lo = window_lo_, old_hi = window_hi_;
  windowed_ = true;
  window_lo_ = lo;
  window_hi_ = hi;
  if (!current) return;  // the next refresh() rebuilds within the stretch
  if (was && lo == old_lo && hi == old_hi) return;
  drop_outside();
  if (!was) return;  // every brick was held
  if (hi < old_lo || lo > old_hi) {
    admit(map, lo, hi);
  } else {
    if (lo < old_lo) admit(map, lo, old_lo - 1);
    if (hi > old_hi) admit(map, old_hi + 1, hi);
  }
}

void VoxelIndex::keep_all(const mapping::SemanticOcTree& map) {
  if (!windowed_) return;
  windowed_ = false;
  if (!(map_ == &map && revision_ == map.revision() && resolution_ == map.getResolution())) return;
  if (window_lo_ > 0) admit(map, 0, window_lo_ - 1);
  if (window_hi_ < 0xffffu >> kBrickBits) admit(map, window_hi_ + 1, 0xffffu >> kBrickBits);
  dropped_stamps_.clear();
}

bool VoxelIndex::changed_since(std::uint64_t since, const std::vector<std::uint64_t>& brick_keys) const {
  if (since >= generation_) return false;
  if (since < rebuilt_at_) return true;
  if (table_keys_.empty()) return false;
  for (const std::uint64_t bk : brick_keys) {
    const std::uint32_t* b = brick(bk);  // absent now, so absent then: all unknown (unless dropped)
    if (b && brick_stamps_[std::size_t(b - cells_.data()) / kBrickCells] > since) return true;
    if (!b && dropped_x(brick_x(bk))) {
      const auto it = dropped_stamps_.find(bk);
      if (it != dropped_stamps_.end() && it->second > since) return true;
    }
  }
  return false;
}

std::size_t VoxelIndex::max_voxels(double length_m) const {
  if (!(resolution_ > 0.0) || !std::isfinite(length_m)) return 0;
  return static_cast<std::size_t>(3.0 * (length_m / resolution_ + 2.0)) + 4;
}

std::size_t VoxelIndex::memory_bytes() const {
  return palette_.capacity() * sizeof(VoxelInfo) + cells_.capacity() * sizeof(std::uint32_t) +
         brick_keys_.capacity() * 8 + brick_stamps_.capacity() * 8 + table_keys_.capacity() * 8 +
         table_values_.capacity() * 4 + dropped_stamps_.size() * 32;
}

std::size_t VoxelIndex::cast(const Vec3& origin_d, const Vec3& end_d, const Vec3& target, RayVoxel* out,
                             std::size_t capacity, bool* outside, octomap::OcTreeKey* keys,
                             std::vector<std::uint64_t>* bricks) const {
  if (outside) *outside = false;
  CANOPY_CHECK(map_ != nullptr, "VoxelIndex::cast before rebuild");
  // Float end points, as OctoMap's computeRayKeys takes them (mapping/voxel_ray.h).
  const octomap::point3d origin(float(origin_d.x()), float(origin_d.y()), float(origin_d.z()));
  const octomap::point3d end(float(end_d.x()), float(end_d.y()), float(end_d.z()));
  if (capacity == 0) {
    octomap::OcTreeKey k;
    if (outside) *outside = !map_->coordToKeyChecked(origin, k) || !map_->coordToKeyChecked(end, k);
    return 0;
  }
  std::size_t n = 0;
  std::uint64_t cached_bk = kEmpty;
  const std::uint32_t* cached = nullptr;
  bool dropped = false;
  const double res = resolution_;
  const double tx0 = target.x(), ty0 = target.y(), tz0 = target.z();
  const bool inside = mapping::walk_ray(*map_, origin, end, [&](unsigned x, unsigned y, unsigned z) {
    const std::uint64_t bk = mapping::brick_key(x, y, z);
    if (bk != cached_bk) {
      cached_bk = bk;
      cached = brick(bk);
      dropped = !cached && dropped_x(x >> kBrickBits);
      if (bricks) bricks->push_back(bk);
    }
    const std::uint32_t id = cached ? cached[mapping::brick_cell(x, y, z)] : dropped ? map_id(x, y, z) : 0u;
    const double cx = mapping::key_center(x, res) - tx0;
    const double cy = mapping::key_center(y, res) - ty0;
    const double cz = mapping::key_center(z, res) - tz0;
    if (keys) keys[n] = octomap::OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                                           static_cast<octomap::key_type>(z));
    out[n].info = &palette_[id];
    out[n].id = id;
    out[n].dist2_m2 = float(cx * cx + cy * cy + cz * cz);
    return ++n < capacity;
  });
  if (!inside && outside) *outside = true;
  return n;
}

bool cast_reference(const mapping::SemanticOcTree& map, const Vec3& origin, const Vec3& end,
                    octomap::KeyRay* scratch, std::vector<ReferenceVoxel>* out) {
  const octomap::point3d o(float(origin.x()), float(origin.y()), float(origin.z()));
  const octomap::point3d e(float(end.x()), float(end.y()), float(end.z()));
  if (!map.computeRayKeys(o, e, *scratch)) return false;
  for (const octomap::OcTreeKey& k : *scratch) out->push_back({k, map.find(k)});
  return true;
}

}  // namespace canopy::nbv
