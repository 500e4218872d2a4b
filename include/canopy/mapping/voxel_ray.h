#pragma once
// The one voxel walk of the project: an Amanatides-Woo traversal of the segment origin -> end
// at the map's resolution, step for step the arithmetic of OctoMap's
// OcTreeBaseImpl::computeRayKeys (float end points, double boundaries, ties broken towards z,
// then y), so every caller visits exactly the voxels OctoMap would. Scan insertion carves free
// space with it (walk_rays: many segments at once, four per AVX2 register) and the
// next-best-view index casts its rays with it.

// OctoMap's OcTreeKey.h uses uint16_t, size_t and std::vector without including their headers.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include <cmath>
#include <immintrin.h>
#include <limits>
#include <stdexcept>

namespace canopy::mapping {

/// A walk after its set-up: the parameter of the next boundary and the step between
/// boundaries per axis, the current and the end voxel, the step direction (-1 wraps), the
/// segment's length.
struct RayWalk {
  double t[3], d[3];
  unsigned k[3], e[3], s[3];
  double len;
};

/// Sets up the walk of `origin` -> `end` (computeRayKeys' arithmetic): false when an end lies
/// outside the tree (`*outside` true) or both ends share a voxel (nothing to visit).
template <typename Tree>
bool start_walk(const Tree& tree, const octomap::point3d& origin, const octomap::point3d& end, RayWalk* w,
                bool* outside) {
  octomap::OcTreeKey key_origin, key_end;
  *outside = !tree.coordToKeyChecked(origin, key_origin) || !tree.coordToKeyChecked(end, key_end);
  if (*outside || key_origin == key_end) return false;
  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;
  const double res = tree.getResolution();
  for (unsigned i = 0; i < 3; ++i) {
    const int step = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    w->s[i] = unsigned(step);
    if (step != 0) {
      double border = tree.keyToCoord(key_origin[i]);
      border += float(step * res * 0.5);
      w->t[i] = (border - origin(i)) / direction(i);
      w->d[i] = res / std::fabs(direction(i));
    } else {
      w->t[i] = std::numeric_limits<double>::max();
      w->d[i] = std::numeric_limits<double>::max();
    }
    w->k[i] = key_origin[i];
    w->e[i] = key_end[i];
  }
  w->len = length;
  return true;
}

/// Walks the voxels of the segment `origin` -> `end` in order, the origin's voxel first and the
/// end's voxel left out (computeRayKeys' set), calling visit(x, y, z) with each voxel's key
/// coordinates; a visit returning false ends the walk. `tree` is an OctoMap tree (its
/// coordToKeyChecked and keyToCoord give the keys and boundaries). Returns false, visiting
/// nothing, when an end lies outside the tree; both ends in one voxel visit nothing.
template <typename Tree, typename Visit>
bool walk_ray(const Tree& tree, const octomap::point3d& origin, const octomap::point3d& end, Visit&& visit) {
  RayWalk w;
  bool outside = false;
  if (!start_walk(tree, origin, end, &w, &outside)) return !outside;
  if (!visit(w.k[0], w.k[1], w.k[2])) return true;
  // The loop state in scalars (registers), not arrays indexed by the axis.
  double tx = w.t[0], ty = w.t[1], tz = w.t[2];
  const double dx = w.d[0], dy = w.d[1], dz = w.d[2];
  const unsigned sx = w.s[0], sy = w.s[1], sz = w.s[2];
  unsigned kx = w.k[0], ky = w.k[1], kz = w.k[2];
  const unsigned ex = w.e[0], ey = w.e[1], ez = w.e[2];
  const double len = w.len;
  for (;;) {
    // Step along the axis of the nearest boundary (ties as computeRayKeys: 2 over 1 over 0).
    if (tx < ty) {
      if (tx < tz) {
        kx = (kx + sx) & 0xFFFFu;
        tx += dx;
      } else {
        kz = (kz + sz) & 0xFFFFu;
        tz += dz;
      }
    } else if (ty < tz) {
      ky = (ky + sy) & 0xFFFFu;
      ty += dy;
    } else {
      kz = (kz + sz) & 0xFFFFu;
      tz += dz;
    }
    if (kx == ex && ky == ey && kz == ez) return true;
    if (std::min(std::min(tx, ty), tz) > len) return true;
    if (!visit(kx, ky, kz)) return true;
  }
}

namespace detail {
using V4d = double __attribute__((vector_size(32)));
using V4l = long long __attribute__((vector_size(32)));

// walk_rays on four rays at a time in AVX2 lanes: each lane steps as walk_ray (the same
// double additions and comparisons, ties alike); a lane whose ray ends takes the next ray.
// A ray's first voxel goes to visit(x, y, z); the voxels of a step go to
// visit4(kx, ky, kz, lanes) at once, lanes[l] = -1 for each lane that visits.
template <typename Tree, typename Segment, typename Visit, typename Visit4>
__attribute__((target("avx2"))) void walk_rays_avx2(const Tree& tree, std::size_t n, Segment& segment,
                                                    Visit& visit, const Visit4& visit4_in) {
  // A copy whose address is not taken: stores of the visits (which may alias anything of
  // their type) cannot change it, so what it holds stays in registers or is loaded unchanged.
  const Visit4 visit4 = visit4_in;
  V4d tx{}, ty{}, tz{}, dx{}, dy{}, dz{}, len{};
  V4l kx{}, ky{}, kz{}, sx{}, sy{}, sz{}, ex{}, ey{}, ez{};
  // Lanes without a ray: a bit each here, and a length below every boundary parameter (those
  // are >= 0), so that they always count as stopped without a vector of their own.
  int dead = 0;
  std::size_t next = 0;
  auto refill = [&](int l) {
    RayWalk w;
    bool outside = false;
    while (next < n) {
      octomap::point3d a, b;
      segment(next++, &a, &b);
      if (!start_walk(tree, a, b, &w, &outside)) continue;
      visit(w.k[0], w.k[1], w.k[2]);
      tx[l] = w.t[0], ty[l] = w.t[1], tz[l] = w.t[2];
      dx[l] = w.d[0], dy[l] = w.d[1], dz[l] = w.d[2];
      kx[l] = w.k[0], ky[l] = w.k[1], kz[l] = w.k[2];
      sx[l] = static_cast<int>(w.s[0]), sy[l] = static_cast<int>(w.s[1]), sz[l] = static_cast<int>(w.s[2]);
      ex[l] = w.e[0], ey[l] = w.e[1], ez[l] = w.e[2];
      len[l] = w.len;
      return true;
    }
    dead |= 1 << l;
    len[l] = -1.0;
    return false;
  };
  int alive = 0;
  for (int l = 0; l < 4; ++l) alive += refill(l);
  const V4l mask16 = {0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF};
  const V4l all = {-1, -1, -1, -1};
  while (alive > 0) {
    const V4l xy = tx < ty, xz = tx < tz, yz = ty < tz;
    const V4l cx = xy & xz, cy = ~xy & yz, cz = ~(cx | cy);
    kx = (kx + (sx & cx)) & mask16;
    ky = (ky + (sy & cy)) & mask16;
    kz = (kz + (sz & cz)) & mask16;
    tx += reinterpret_cast<V4d>(reinterpret_cast<V4l>(dx) & cx);
    ty += reinterpret_cast<V4d>(reinterpret_cast<V4l>(dy) & cy);
    tz += reinterpret_cast<V4d>(reinterpret_cast<V4l>(dz) & cz);
    // The least of the three (never NaN): the value the ternaries of walk_ray pick.
    const V4d m = V4d(_mm256_min_pd(__m256d(tx), _mm256_min_pd(__m256d(ty), __m256d(tz))));
    const V4l stop = ((kx == ex) & (ky == ey) & (kz == ez)) | (m > len);
    const int stopped = _mm256_movemask_pd(__m256d(stop));
    if (stopped == 0) {
      visit4(kx, ky, kz, all);
      continue;
    }
    if (stopped != 0xF) visit4(kx, ky, kz, ~stop);
    for (int l = 0; l < 4; ++l)
      if (!(dead >> l & 1) && (stopped >> l & 1) && !refill(l)) --alive;
  }
}
}  // namespace detail

/// A box of voxel keys, [lo, lo + n) per axis, with one bit per cell in `words` (x fastest:
/// cell (x, y, z) of the box is bit c % 64 of word c / 64, c = (z * n[1] + y) * n[0] + x).
/// Sets the bit of each key it is given that lies in the box; keys outside it are ignored.
/// A bit per cell keeps a grid of a scan's box (some 10^5 cells) in the first-level cache;
/// a grid per thread keeps cache lines unshared.
struct KeyBitGrid {
  int lo[3] = {0, 0, 0};
  int n[3] = {0, 0, 0};
  std::uint64_t* words = nullptr;

  std::size_t size() const { return std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]); }
  /// Words holding size() bits.
  std::size_t word_count() const { return (size() + 63) / 64; }
  void operator()(unsigned kx, unsigned ky, unsigned kz) const {
    const int x = int(kx) - lo[0], y = int(ky) - lo[1], z = int(kz) - lo[2];
    if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2]) return;
    const std::size_t c = (std::size_t(z) * std::size_t(n[1]) + std::size_t(y)) * std::size_t(n[0]) + std::size_t(x);
    words[c / 64] |= std::uint64_t(1) << (c % 64);
  }
};

namespace detail {
// A KeyBitGrid as walk_rays_avx2's visit4: the box's bounds broadcast to the lanes once, and
// the lanes' cell indices, bounds tests and bits computed in the lanes.
struct KeyBitGridLanes {
  V4l lo0, lo1, lo2, n0, n1, n2;
  std::uint64_t* words;

  explicit KeyBitGridLanes(const KeyBitGrid& g)
      : lo0{g.lo[0], g.lo[0], g.lo[0], g.lo[0]}, lo1{g.lo[1], g.lo[1], g.lo[1], g.lo[1]},
        lo2{g.lo[2], g.lo[2], g.lo[2], g.lo[2]}, n0{g.n[0], g.n[0], g.n[0], g.n[0]},
        n1{g.n[1], g.n[1], g.n[1], g.n[1]}, n2{g.n[2], g.n[2], g.n[2], g.n[2]}, words(g.words) {}

  __attribute__((target("avx2"))) void operator()(const V4l& kx, const V4l& ky, const V4l& kz, const V4l& lanes) const {
    const V4l zero = {0, 0, 0, 0}, low6 = {63, 63, 63, 63}, one = {1, 1, 1, 1};
    const V4l x = kx - lo0, y = ky - lo1, z = kz - lo2;
    // In the box: no coordinate negative (the sign of their union) and each below its extent.
    const V4l in = lanes & ~(zero > (x | y | z)) & (x < n0) & (y < n1) & (z < n2);
    // The lane multiply takes 32 bits: z * n[1] + y < n[1] * n[2] and every factor of a box
    // of fewer than 2^32 cells fit.
    const V4l c = V4l(_mm256_mul_epu32(__m256i(V4l(_mm256_mul_epu32(__m256i(z), __m256i(n1))) + y), __m256i(n0))) + x;
    const V4l w = V4l(_mm256_srli_epi64(__m256i(c), 6));
    const V4l bit = V4l(_mm256_sllv_epi64(__m256i(one), __m256i(c & low6)));
    std::uint64_t* const g = words;
    if (_mm256_movemask_pd(__m256d(in)) == 0xF) {
      g[w[0]] |= std::uint64_t(bit[0]), g[w[1]] |= std::uint64_t(bit[1]);
      g[w[2]] |= std::uint64_t(bit[2]), g[w[3]] |= std::uint64_t(bit[3]);
      return;
    }
    for (int l = 0; l < 4; ++l)
      if (in[l]) g[w[l]] |= std::uint64_t(bit[l]);
  }
};
}  // namespace detail

/// Walks every segment i < n (segment(i, &origin, &end)) as walk_ray does, visiting each
/// segment's voxels in no set order across segments: the union of their walks, for callers
/// that only mark voxels (free-space carving). Uses AVX2 lanes when the processor has them
/// and `vectorised` is true (the same voxels: tests compare both).
template <typename Tree, typename Segment, typename Visit>
void walk_rays(const Tree& tree, std::size_t n, Segment&& segment, Visit&& visit, bool vectorised = true) {
  if (vectorised && __builtin_cpu_supports("avx2")) {
    auto lanes = [&visit](const detail::V4l& kx, const detail::V4l& ky, const detail::V4l& kz,
                          const detail::V4l& on) {
      for (int l = 0; l < 4; ++l)
        if (on[l]) visit(unsigned(kx[l]), unsigned(ky[l]), unsigned(kz[l]));
    };
    detail::walk_rays_avx2(tree, n, segment, visit, lanes);
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    octomap::point3d a, b;
    segment(i, &a, &b);
    walk_ray(tree, a, b, [&](unsigned x, unsigned y, unsigned z) {
      visit(x, y, z);
      return true;
    });
  }
}

/// Marks in `grid` every voxel of every segment i < n (segment(i, &origin, &end)) that
/// walk_ray visits and that lies in the grid's box: walk_rays with a visit that sets the
/// cell's bit, its index computed in the AVX2 lanes themselves when `vectorised` (the same
/// cells either way: tests compare both). The grid must have fewer than 2^32 cells.
template <typename Tree, typename Segment>
void mark_walked_voxels(const Tree& tree, std::size_t n, Segment&& segment, const KeyBitGrid& grid,
                        bool vectorised = true) {
  if (grid.n[0] < 0 || grid.n[1] < 0 || grid.n[2] < 0 || grid.size() >= (std::uint64_t(1) << 32))
    throw std::length_error("mark_walked_voxels: the grid must have fewer than 2^32 cells");
  KeyBitGrid g = grid;
  if (vectorised && __builtin_cpu_supports("avx2")) {
    detail::walk_rays_avx2(tree, n, segment, g, detail::KeyBitGridLanes(g));
    return;
  }
  walk_rays(tree, n, segment, g, false);
}

}  // namespace canopy::mapping
