#pragma once
// Every way canopy names a voxel by integers, in one place (nvblox keeps its indexing the same
// way, in core/indexing.h):
//  - OctoMap keys: 16 bits per axis, key = floor(x / resolution) + 2^15 (a 16-level tree);
//    point_key() is OctoMap's coordToKeyChecked with an inline floor;
//  - Morton codes: the three 16-bit key coordinates interleaved (x in bit 0, y in bit 1, z in
//    bit 2 of every triple), so sorting codes sorts voxels in the tree's depth-first order;
//  - bricks: 8 x 8 x 8 voxels, named by the key's upper 13 bits per axis, with a 9-bit cell
//    index inside (the NBV voxel index's layout);
//  - grid keys: unbounded cubic grids of any edge (the ground truth's voxels), 21 bits per axis
//    around the origin (about +-15 km at 1.5 cm).

// OctoMap's OcTreeKey.h uses uint16_t, size_t and std::vector without including their headers.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>

#include <cmath>

#include "canopy/common/types.h"

namespace canopy::mapping {

/// Levels of the octree (OctoMap's fixed 16).
constexpr unsigned kOctreeDepth = 16;
/// The key of the voxel whose lower corner is the world origin: 2^15.
constexpr int kKeyOrigin = 1 << 15;

// --- OctoMap keys ------------------------------------------------------------------------

/// OctoMap's coordToKeyChecked (key = floor(x / res) + 2^15, false outside the tree), with an
/// inline floor: libm's floor is a call per coordinate on baseline x86-64. `inv_res` = 1 / res.
inline bool point_key(const Vec3f& p, double inv_res, octomap::OcTreeKey* key) {
  for (int a = 0; a < 3; ++a) {
    const double v = inv_res * double(p[a]);
    if (!(v > -32769.0 && v < 32769.0)) return false;
    int i = static_cast<int>(v);
    i -= v < i;
    i += kKeyOrigin;
    if (i < 0 || i >= 65536) return false;
    (*key)[a] = static_cast<octomap::key_type>(i);
  }
  return true;
}

/// Centre coordinate of key coordinate `k` at `resolution` (OctoMap's keyToCoord).
inline double key_center(unsigned k, double resolution) {
  return (double(static_cast<int>(k) - kKeyOrigin) + 0.5) * resolution;
}

// --- Morton codes ------------------------------------------------------------------------

namespace detail {
/// Spreads the 16 bits of v so that bit i lands on bit 3i.
inline std::uint64_t spread3(std::uint64_t v) {
  v &= 0xffff;
  v = (v | (v << 16)) & 0x0000ff0000ffull;
  v = (v | (v << 8)) & 0x00f00f00f00full;
  v = (v | (v << 4)) & 0x0c30c30c30c3ull;
  v = (v | (v << 2)) & 0x249249249249ull;
  return v;
}
/// Inverse of spread3.
inline std::uint16_t compact3(std::uint64_t v) {
  v &= 0x249249249249ull;
  v = (v | (v >> 2)) & 0x0c30c30c30c3ull;
  v = (v | (v >> 4)) & 0x00f00f00f00full;
  v = (v | (v >> 8)) & 0x0000ff0000ffull;
  v = (v | (v >> 16)) & 0xffff;
  return static_cast<std::uint16_t>(v);
}
}  // namespace detail

/// The Morton code of a key (48 bits).
inline std::uint64_t morton_code(const octomap::OcTreeKey& key) {
  return detail::spread3(key[0]) | (detail::spread3(key[1]) << 1) | (detail::spread3(key[2]) << 2);
}
/// Inverse of morton_code.
inline octomap::OcTreeKey morton_key(std::uint64_t code) {
  return octomap::OcTreeKey(detail::compact3(code), detail::compact3(code >> 1), detail::compact3(code >> 2));
}
/// Deepest tree depth whose node lies on the paths of both codes (kOctreeDepth when equal).
inline unsigned morton_common_depth(std::uint64_t a, std::uint64_t b) {
  const std::uint64_t x = a ^ b;
  if (x == 0) return kOctreeDepth;
  const unsigned level = (63u - static_cast<unsigned>(__builtin_clzll(x))) / 3u;  // 0..15
  return kOctreeDepth - 1 - level;
}
/// Index (0..7) of the child taken at `depth` on the path to `code`.
inline unsigned morton_child(std::uint64_t code, unsigned depth) {
  return static_cast<unsigned>(code >> (3 * (kOctreeDepth - 1 - depth))) & 7u;
}

// --- Bricks of 8^3 voxels ----------------------------------------------------------------

constexpr int kBrickBits = 3;                 ///< Bricks of 2^3 = 8 voxels a side.
constexpr int kBrickSide = 1 << kBrickBits;
constexpr int kBrickCells = kBrickSide * kBrickSide * kBrickSide;

/// Brick of the voxel with key coordinates (x, y, z): 13 bits per axis.
inline std::uint64_t brick_key(unsigned x, unsigned y, unsigned z) {
  return std::uint64_t(x >> kBrickBits) | (std::uint64_t(y >> kBrickBits) << 13) |
         (std::uint64_t(z >> kBrickBits) << 26);
}
inline std::uint64_t brick_key(const octomap::OcTreeKey& k) { return brick_key(k[0], k[1], k[2]); }
/// Brick key from brick coordinates (key coordinate >> kBrickBits).
inline std::uint64_t brick_key_of_brick(unsigned bx, unsigned by, unsigned bz) {
  return std::uint64_t(bx) | (std::uint64_t(by) << 13) | (std::uint64_t(bz) << 26);
}
/// Cell of the voxel (x, y, z) inside its brick (0..kBrickCells-1).
inline unsigned brick_cell(unsigned x, unsigned y, unsigned z) {
  constexpr unsigned m = kBrickSide - 1;
  return (x & m) | ((y & m) << kBrickBits) | ((z & m) << (2 * kBrickBits));
}

// --- Grid keys of any edge -------------------------------------------------------------

constexpr int kGridBits = 21;
constexpr std::int64_t kGridOrigin = std::int64_t{1} << (kGridBits - 1);

/// A cell of an unbounded cubic grid: floor(p / res) per axis.
using GridCell = Eigen::Array<std::int64_t, 3, 1>;
/// The cell of point p on a cubic grid of edge `res`.
inline GridCell grid_cell(const Vec3& p, double res) { return (p / res).array().floor().cast<std::int64_t>(); }
/// The grid key of a cell (21 bits per axis around the origin).
inline std::uint64_t grid_key(const GridCell& cell) {
  const GridCell k = cell + kGridOrigin;
  return (static_cast<std::uint64_t>(k.x()) << (2 * kGridBits)) | (static_cast<std::uint64_t>(k.y()) << kGridBits) |
         static_cast<std::uint64_t>(k.z());
}
/// The grid key of point p on a cubic grid of edge `res` (its cell's key).
inline std::uint64_t grid_key(const Vec3& p, double res) { return grid_key(grid_cell(p, res)); }
/// Centre of the cell with grid key `key`.
inline Vec3 grid_center(std::uint64_t key, double res) {
  constexpr std::uint64_t mask = (std::uint64_t{1} << kGridBits) - 1;
  const auto unpack = [&](int shift) {
    return static_cast<double>(static_cast<std::int64_t>((key >> shift) & mask) - kGridOrigin);
  };
  return Vec3((unpack(2 * kGridBits) + 0.5) * res, (unpack(kGridBits) + 0.5) * res, (unpack(0) + 0.5) * res);
}

}  // namespace canopy::mapping
