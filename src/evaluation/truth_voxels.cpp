#include "canopy/evaluation/truth_voxels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <queue>
#include <utility>

#include <immintrin.h>

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

// The keys a plant's samples give, each once, handed back sorted. Keys of the cells in a box
// (the plant's, from its vertices) set bits of a bit grid whose order is the keys' (x, then y,
// then z, from low to high: a key packs the cell's x, y and z from its high bits down), so
// reading the bits back gives them sorted and once; any other key (none when the box holds the
// plant's samples) goes to a list sorted at the end and merged in. Without a box (`use_box`
// false, or one past 2^28 cells) every key goes to the list.
class KeySet {
 public:
  KeySet(const world::Plant& plant, double res, bool use_box) {
    if (!use_box) return;
    Eigen::Array3d lo = Eigen::Array3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& part : plant.parts)
      for (const Vec3& v : part.mesh.vertices) {
        lo = lo.min(v.array());
        hi = hi.max(v.array());
      }
    // A cell either side of the vertices' cells: samples are the vertices' weighted sums.
    const Eigen::Array3d first = (lo / res).floor() - 1.0, last = (hi / res).floor() + 1.0;
    const double limit = double(mapping::kGridOrigin) - 2.0;
    if (!(first.allFinite() && last.allFinite() && first.abs().maxCoeff() < limit && last.abs().maxCoeff() < limit))
      return;
    const Eigen::Array3d size = last - first + 1.0;
    if (size.prod() > double(std::uint64_t{1} << 28)) return;
    for (int axis = 0; axis < 3; ++axis) {
      first_[axis] = static_cast<std::uint64_t>(static_cast<std::int64_t>(first[axis]) + mapping::kGridOrigin);
      size_[axis] = static_cast<std::uint64_t>(size[axis]);
    }
    bits_.assign((size_[0] * size_[1] * size_[2] + 63) / 64, 0);
  }

  void add(std::uint64_t key) {
    constexpr std::uint64_t mask = (std::uint64_t{1} << mapping::kGridBits) - 1;
    const std::uint64_t x = (key >> (2 * mapping::kGridBits)) - first_[0], y = ((key >> mapping::kGridBits) & mask) - first_[1],
                        z = (key & mask) - first_[2];
    if (!bits_.empty() && x < size_[0] && y < size_[1] && z < size_[2]) {
      const std::uint64_t at = (x * size_[1] + y) * size_[2] + z;
      bits_[at >> 6] |= std::uint64_t{1} << (at & 63);
    } else {
      outside_.push_back(key);
    }
  }

  std::vector<std::uint64_t> sorted(std::vector<std::uint64_t>& scratch) {
    radix_sort_u64(outside_, scratch);
    outside_.erase(std::unique(outside_.begin(), outside_.end()), outside_.end());
    if (bits_.empty()) {
      outside_.shrink_to_fit();
      return std::move(outside_);
    }
    std::vector<std::uint64_t> inside;
    std::size_t count = 0;
    for (const std::uint64_t w : bits_) count += static_cast<std::size_t>(__builtin_popcountll(w));
    inside.reserve(count);
    for (std::size_t word = 0; word < bits_.size(); ++word)
      for (std::uint64_t w = bits_[word]; w != 0; w &= w - 1) {
        const std::uint64_t at = word * 64 + static_cast<std::uint64_t>(__builtin_ctzll(w));
        const std::uint64_t z = at % size_[2], y = (at / size_[2]) % size_[1], x = at / (size_[2] * size_[1]);
        inside.push_back(((x + first_[0]) << (2 * mapping::kGridBits)) | ((y + first_[1]) << mapping::kGridBits) |
                         (z + first_[2]));
      }
    if (outside_.empty()) return inside;
    std::vector<std::uint64_t> all(inside.size() + outside_.size());
    all.erase(std::set_union(inside.begin(), inside.end(), outside_.begin(), outside_.end(), all.begin()), all.end());
    all.shrink_to_fit();
    return all;
  }

 private:
  std::uint64_t first_[3] = {0, 0, 0}, size_[3] = {0, 0, 0};
  std::vector<std::uint64_t> bits_;     // the box's cells, x-major
  std::vector<std::uint64_t> outside_;  // keys outside the box
};

// Appends the first `lanes` keys of out[] unless one is the key appended before it.
inline void append_keys(const std::uint64_t* out, std::size_t lanes, std::uint64_t& last, bool& any, KeySet& keys) {
  for (std::size_t l = 0; l < lanes; ++l) {
    if (any && out[l] == last) continue;
    keys.add(out[l]);
    last = out[l];
    any = true;
  }
}

// A triangle's samples (barycentric steps of 1/n: closer than half a voxel when n is the
// longest edge over half a voxel), each sample's key appended unless it is the last one's
// (neighbouring samples mostly share a voxel).
void triangle_keys(const Vec3& a, const Vec3& b, const Vec3& c, int n, double res, KeySet& keys) {
  std::uint64_t last = 0;
  bool any = false;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n - i; ++j) {
      const std::uint64_t k = mapping::grid_key(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n), res);
      append_keys(&k, 1, last, any, keys);
    }
}

// The keys of four samples (barycentric sv and tv in the lanes) of the triangle whose first vertex
// and edges (b - a, c - a) are a[], ba[], ca[] (one axis each, in every lane): the scalar
// code's operations in its order, with no fused multiply-add (the target has none), so the
// same doubles and the same keys. A cell is the floor of the sample over the voxel, taken from
// the product with the voxel's reciprocal where that lies more than 1e-6 of a voxel from a voxel
// face (products and quotients differ by a few units in the last place, 2.4e-7 of a voxel at
// 2^29 voxels: the same floor), else from the quotient as the scalar code does. The cells must
// lie within 2^29 voxels of the origin (the caller checks).
__attribute__((target("avx2"), always_inline)) inline void sample_keys_avx2(const __m256d* a, const __m256d* ba,
                                                                            const __m256d* ca, __m256d sv, __m256d tv,
                                                                            __m256d res, __m256d inverse,
                                                                            std::uint64_t* out) {
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
  const __m256d tolerance = _mm256_set1_pd(1e-6);
  __m256i key = _mm256_setzero_si256();
  for (int axis = 0; axis < 3; ++axis) {
    const __m256d p = _mm256_add_pd(_mm256_add_pd(a[axis], _mm256_mul_pd(ba[axis], sv)), _mm256_mul_pd(ca[axis], tv));
    const __m256d q = _mm256_mul_pd(p, inverse);
    const __m256d off = _mm256_and_pd(_mm256_sub_pd(q, _mm256_round_pd(q, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC)), magnitude);
    const bool face = _mm256_movemask_pd(_mm256_cmp_pd(off, tolerance, _CMP_LE_OQ)) != 0;
    const __m256d cell = _mm256_floor_pd(face ? _mm256_div_pd(p, res) : q);
    const __m256i k = _mm256_add_epi64(_mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(cell)), _mm256_set1_epi64x(mapping::kGridOrigin));
    key = _mm256_or_si256(_mm256_slli_epi64(key, mapping::kGridBits), k);
  }
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), key);
}

// A triangle's samples of triangle_keys for one n, in its order: the barycentric fractions
// i / n and j / n (each the scalar code's quotient), padded to whole lanes of four. Built once
// per n and kept (a plant's triangles share a few small n), so the lanes load them from memory
// written long before.
struct SampleTable {
  std::vector<double> s, t;
  std::size_t count = 0;
};
constexpr int kMaxTabledN = 24;  // past it, a triangle's samples row by row

const SampleTable& sample_table(int n, std::vector<SampleTable>& tables) {
  if (tables.size() <= static_cast<std::size_t>(n)) tables.resize(static_cast<std::size_t>(n) + 1);
  SampleTable& table = tables[static_cast<std::size_t>(n)];
  if (table.count > 0) return table;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n - i; ++j) {
      table.s.push_back(double(i) / n);
      table.t.push_back(double(j) / n);
    }
  table.count = table.s.size();
  table.s.resize((table.count + 3) / 4 * 4, 0.0);  // lanes past the last sample: ignored
  table.t.resize(table.s.size(), 0.0);
  return table;
}

// triangle_keys with four samples at a time in AVX2 lanes: the same keys in the same order.
// Small n from the n's table; larger n row by row (i fixed, four j at a time), the fractions
// j / n from `fractions` (computed once per triangle, padded to whole lanes).
__attribute__((target("avx2"))) void triangle_keys_avx2(const Vec3& a, const Vec3& b, const Vec3& c, int n, double res,
                                                        std::vector<SampleTable>& tables,
                                                        std::vector<double>& fractions, KeySet& keys) {
  const Vec3 ba = b - a, ca = c - a;
  const __m256d av[3] = {_mm256_set1_pd(a.x()), _mm256_set1_pd(a.y()), _mm256_set1_pd(a.z())};
  const __m256d bav[3] = {_mm256_set1_pd(ba.x()), _mm256_set1_pd(ba.y()), _mm256_set1_pd(ba.z())};
  const __m256d cav[3] = {_mm256_set1_pd(ca.x()), _mm256_set1_pd(ca.y()), _mm256_set1_pd(ca.z())};
  const __m256d rd = _mm256_set1_pd(res), inverse = _mm256_set1_pd(1.0 / res);
  std::uint64_t out[4], last = 0;
  bool any = false;
  if (n <= kMaxTabledN) {
    const SampleTable& table = sample_table(n, tables);
    for (std::size_t k = 0; k < table.count; k += 4) {
      sample_keys_avx2(av, bav, cav, _mm256_loadu_pd(table.s.data() + k), _mm256_loadu_pd(table.t.data() + k), rd,
                       inverse, out);
      append_keys(out, std::min<std::size_t>(4, table.count - k), last, any, keys);
    }
    return;
  }
  fractions.assign(static_cast<std::size_t>(n) + 4, 0.0);
  for (int i = 0; i <= n; ++i) fractions[static_cast<std::size_t>(i)] = double(i) / n;
  for (int i = 0; i <= n; ++i) {
    const __m256d sv = _mm256_set1_pd(fractions[static_cast<std::size_t>(i)]);
    const std::size_t row = static_cast<std::size_t>(n - i) + 1;
    for (std::size_t j = 0; j < row; j += 4) {
      sample_keys_avx2(av, bav, cav, sv, _mm256_loadu_pd(fractions.data() + j), rd, inverse, out);
      append_keys(out, std::min<std::size_t>(4, row - j), last, any, keys);
    }
  }
}

// The keys (sorted, each once) of every sample of a plant's surfaces, samples closer than half
// a voxel so that no voxel is skipped. `vectorised`: samples in AVX2 lanes (when the processor
// has them) into the bit grid of the plant's box; else the reference, scalar samples and every
// key radix-sorted (a plant's hundreds of thousands).
std::vector<std::uint64_t> plant_keys(const world::Plant& plant, double res, std::vector<std::uint64_t>* scratch,
                                      bool vectorised = true) {
  const bool avx2 = vectorised && __builtin_cpu_supports("avx2");
  // Lanes convert cells through 32 bits: a triangle far out (cells past 2^29) takes the scalar code.
  const double lane_limit = std::ldexp(res, 29);
  KeySet keys(plant, res, vectorised);
  std::vector<SampleTable> tables;
  std::vector<double> fractions;
  const double step = 0.5 * res;
  for (const auto& part : plant.parts) {
    const auto& v = part.mesh.vertices;
    for (const auto& f : part.mesh.faces) {
      const Vec3 &a = v[static_cast<size_t>(f[0])], &b = v[static_cast<size_t>(f[1])], &c = v[static_cast<size_t>(f[2])];
      const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
      const int n = std::max(1, static_cast<int>(std::ceil(longest / step)));
      const auto near = [&] {
        return a.cwiseAbs().maxCoeff() < lane_limit && b.cwiseAbs().maxCoeff() < lane_limit &&
               c.cwiseAbs().maxCoeff() < lane_limit;
      };
      if (avx2 && near())
        triangle_keys_avx2(a, b, c, n, res, tables, fractions, keys);
      else
        triangle_keys(a, b, c, n, res, keys);
    }
  }
  return keys.sorted(*scratch);  // kept per plant (WindowVoxels): shrunk to size
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

std::vector<std::uint64_t> plant_surface_keys(const world::Plant& plant, double resolution_m, bool vectorised) {
  check_resolution(resolution_m);
  std::vector<std::uint64_t> scratch;
  return plant_keys(plant, resolution_m, &scratch, vectorised);
}

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
