#pragma once
// A flat voxel index kept beside the semantic octree for next-best-view ray casting
// (docs/background/speed_anchors.md), and the two ray traversals that read the map:
//  - fast: the project's one voxel walk (mapping/voxel_ray.h, the same voxels as OctoMap's
//    computeRayKeys) whose lookups go to 8x8x8-voxel bricks (mapping/voxel_key.h) found by an
//    open-addressing hash, with the last brick cached: most steps cost an array read, not a
//    16-level tree descent;
//  - reference: computeRayKeys plus one tree search per key (slow, obviously correct).
//
// Every distinct voxel state is interned once into a palette of VoxelInfo that already holds
// what the gains need (p_occ, entropies, the target flag, SSMI mutual-information terms), so
// the gains do no exp/log per voxel. Palette id 0 is the unknown (never observed) voxel, and
// equal ids mean identical states: the run-length segments of SSMI's MI are runs of one id.

#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>


#include "canopy/common/classes.h"
#include "canopy/common/error.h"
#include "canopy/common/types.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/mapping/voxel_key.h"
#include "canopy/mapping/voxel_ray.h"

namespace canopy::nbv {

/// What the gains need about one voxel state, computed once per distinct state.
struct VoxelInfo {
  static constexpr int kMaxCategories = SemanticClasses::kMaxClasses + 1;  ///< free + the classes.
  bool known = false;          ///< False: never observed (no leaf in the tree).
  bool is_target = false;      ///< Occupied and the most likely class is the target.
  std::int8_t cls = -1;        ///< Most likely stored class; -1 when none (or unknown).
  float p_occ = 0.5f;          ///< Occupancy probability (0.5 when unknown).
  float entropy = 0.f;         ///< Multi-class entropy H(x) in nats (unseen prior when unknown).
  float binary_entropy = 0.f;  ///< H_b(p_occ) in nats.
  // SSMI mutual information over categories {free, class 0..K-1}.
  float prob[kMaxCategories] = {};    ///< Categorical distribution (free first).
  float kl_free = 0.f;                ///< KL(posterior || prior) after a pass-through update.
  float kl_hit[kMaxCategories] = {};  ///< KL after a hit of class k (index k, not k + 1).
};

/// Builds the VoxelInfo of `state` (nullptr: an unknown voxel under the map's unseen prior).
VoxelInfo make_voxel_info(const mapping::SemanticOcTree& map, const mapping::SemanticState* state);

/// One voxel visited by a ray, in order from the camera.
struct RayVoxel {
  const VoxelInfo* info = nullptr;  ///< Never null: unknown voxels point at the unknown entry.
  float dist2_m2 = 0.f;             ///< Squared distance from the voxel centre to the view's target.
  std::uint32_t id = 0;             ///< Palette id (0 = unknown); equal ids = identical states.
};

namespace detail {
/// Bytewise key of a SemanticState for interning (the struct has no padding: 20 bytes).
struct StateBytes {
  std::uint64_t a = 0, b = 0;
  std::uint32_t c = 0;
  explicit StateBytes(const mapping::SemanticState& s) {
    static_assert(sizeof(mapping::SemanticState) == 20, "SemanticState layout changed");
    unsigned char buf[20];
    std::memcpy(buf, &s, 20);
    std::memcpy(&a, buf, 8);
    std::memcpy(&b, buf + 8, 8);
    std::memcpy(&c, buf + 16, 4);
  }
  bool operator==(const StateBytes& o) const { return a == o.a && b == o.b && c == o.c; }
};
struct StateHash {
  std::size_t operator()(const StateBytes& s) const;
};
}  // namespace detail

/// Flat brick-hashed index of a SemanticOcTree's voxels (pruned blocks expanded).
class VoxelIndex {
 public:
  static constexpr int kBrickBits = mapping::kBrickBits;  ///< Bricks of 8^3 voxels (mapping/voxel_key.h).
  static constexpr int kBrickSide = mapping::kBrickSide;
  static constexpr int kBrickCells = mapping::kBrickCells;

  VoxelIndex() = default;
  /// Builds the index of `map` (keeps a pointer; the map must outlive the index).
  explicit VoxelIndex(const mapping::SemanticOcTree& map) { rebuild(map); }

  /// Rebuilds from scratch.
  void rebuild(const mapping::SemanticOcTree& map);
  /// Rebuilds when the map's revision (or the map) changed; true when it did.
  bool refresh(const mapping::SemanticOcTree& map);
  /// Brings the index up to date after one batch of voxel updates (the keys a scan changed,
  /// e.g. ScanInserter::last_updates()), at a cost proportional to the batch, not the map:
  /// when the index was current for `revision_before` (the map's revision before the batch),
  /// the changed voxels are interned and written, and true is returned. Otherwise nothing
  /// changes and false: the next refresh() rebuilds. Lookups then return the same states as
  /// after a rebuild (palette ids may differ; equal ids still mean identical states).
  bool apply_updates(const mapping::SemanticOcTree& map, std::uint64_t revision_before,
                     const std::vector<mapping::VoxelUpdate>& updates);

  /// Holds bricks only for the voxels whose x key lies in [x_lo_m, x_hi_m] (widened to whole
  /// bricks; a long row's stretch near the robot, issue 49) and drops the others, so that the
  /// index's memory is bounded by the stretch, not by the row mapped. Every answer stays the
  /// full index's: a voxel of a dropped brick is read from the map (one tree search, and its
  /// state's palette id, as every state in the map is interned), changed_since() keeps the
  /// dropped bricks' stamps, and a brick that comes back into the stretch is filled from the
  /// map again. Updates outside the stretch intern their states and stamp their bricks as
  /// changed (a change reported that was none only costs a cache). When the index is not
  /// current for `map`, only the stretch is set (the next refresh() builds within it).
  void keep_x(const mapping::SemanticOcTree& map, double x_lo_m, double x_hi_m);
  /// Holds every brick again (filled from the map, as keep_x() fills a stretch).
  void keep_all(const mapping::SemanticOcTree& map);
  /// True while keep_x() bounds the bricks held.
  bool windowed() const { return windowed_; }
  /// Bricks dropped by keep_x() whose stamps are kept (changed_since()).
  std::size_t dropped_bricks() const { return dropped_stamps_.size(); }

  /// Palette id of the voxel with `key` (0 when unknown).
  std::uint32_t lookup(const octomap::OcTreeKey& key) const;
  const VoxelInfo& info(std::uint32_t id) const { return palette_[id]; }
  const VoxelInfo& unknown() const { return palette_[0]; }
  const mapping::SemanticOcTree* map() const { return map_; }

  /// Fast traversal of the segment origin -> end: the voxels OctoMap's computeRayKeys returns
  /// (the origin's voxel first, the end's voxel excluded), at most `capacity` of them written
  /// to `out`. Returns the count; 0 when both ends share a voxel. *outside (when given) is
  /// set when an end lies outside the tree's range (then nothing is visited). `keys`, when
  /// given, receives the visited keys (same capacity); `bricks`, when given, is appended the
  /// brick key (mapping::brick_key) of each run of visited voxels in one brick. No allocation
  /// without `bricks`.
  std::size_t cast(const Vec3& origin, const Vec3& end, const Vec3& target, RayVoxel* out, std::size_t capacity,
                   bool* outside = nullptr, octomap::OcTreeKey* keys = nullptr,
                   std::vector<std::uint64_t>* bricks = nullptr) const;

  /// The voxels cast() visits on origin -> end, in order and at most `capacity` of them, each
  /// one's state given to visit(const VoxelInfo&) until it returns false: for loops that stop
  /// early (at a sight line's first occupied voxel) without writing a buffer. False when an end
  /// lies outside the tree's range (cast()'s *outside; nothing visited).
  template <class Visit>
  bool walk(const Vec3& origin, const Vec3& end, std::size_t capacity, Visit&& visit) const;

  /// Counts the changes of the index: each rebuild and each apply_updates() that changed a
  /// voxel's state.
  std::uint64_t generation() const { return generation_; }
  /// False only when no voxel of the bricks `brick_keys` (mapping::brick_key; bricks absent
  /// then or now included) changed state after generation `since`: what was read from those
  /// bricks then reads the same now. A rebuild after `since` counts as a change everywhere.
  bool changed_since(std::uint64_t since, const std::vector<std::uint64_t>& brick_keys) const;

  /// Upper bound of the voxels a segment of `length_m` can visit.
  std::size_t max_voxels(double length_m) const;

  std::size_t palette_size() const { return palette_.size(); }
  std::size_t brick_count() const { return brick_keys_.size(); }
  std::size_t memory_bytes() const;
  double build_ms() const { return build_ms_; }
  /// Total time spent in apply_updates() [ms].
  double update_ms() const { return update_ms_; }

 private:
  static constexpr std::size_t kMaxPalette = std::size_t(1) << 20;
  std::uint32_t intern(const mapping::SemanticOcTree& map, const mapping::SemanticState& state);
  std::uint32_t* brick_for_insert(std::uint64_t brick_key);
  const std::uint32_t* brick(std::uint64_t brick_key) const;
  void grow();
  void rehash(std::size_t cap);
  // True when bricks of brick x `bx` are not held (keep_x()): their voxels are read from the map.
  bool dropped_x(unsigned bx) const { return windowed_ && (bx < window_lo_ || bx > window_hi_); }
  static unsigned brick_x(std::uint64_t brick_key) { return unsigned(brick_key & 0x1fffu); }
  // Palette id of a voxel of a dropped brick: its state in the map (0 when unknown).
  std::uint32_t map_id(unsigned x, unsigned y, unsigned z) const;
  // Fills the bricks of brick x [lo, hi] (held, absent) from the map; stamps them as they were.
  void admit(const mapping::SemanticOcTree& map, unsigned lo, unsigned hi);
  // Drops the bricks the window does not hold, keeping their stamps.
  void drop_outside();
  std::uint64_t slot(std::uint64_t brick_key) const {
    return (brick_key * 0x9E3779B97F4A7C15ULL) >> table_shift_;
  }

  const mapping::SemanticOcTree* map_ = nullptr;
  std::uint64_t revision_ = ~std::uint64_t{0};
  double resolution_ = 0.0;
  std::vector<VoxelInfo> palette_;
  std::vector<std::uint32_t> cells_;          // brick-major, kBrickCells per brick
  std::vector<std::uint64_t> brick_keys_;     // brick key of each brick (insertion order)
  std::vector<std::uint64_t> brick_stamps_;   // per brick: the generation of its last change
  std::uint64_t generation_ = 0;
  std::uint64_t rebuilt_at_ = 0;              // the generation of the last rebuild
  std::vector<std::uint64_t> table_keys_;     // open addressing: brick key or kEmpty
  std::vector<std::uint32_t> table_values_;   // brick index
  std::uint64_t table_mask_ = 0;
  int table_shift_ = 64;                      // Fibonacci hashing: slot = (key * phi) >> shift
  double build_ms_ = 0.0;
  double update_ms_ = 0.0;
  std::unordered_map<detail::StateBytes, std::uint32_t, detail::StateHash> ids_;  // state -> palette id
  // keep_x(): bricks held only for brick x in [window_lo_, window_hi_]; the dropped bricks'
  // stamps (absent: unchanged since the last rebuild, or never known).
  bool windowed_ = false;
  unsigned window_lo_ = 0, window_hi_ = 0;
  std::unordered_map<std::uint64_t, std::uint64_t> dropped_stamps_;
};

template <class Visit>
bool VoxelIndex::walk(const Vec3& origin_d, const Vec3& end_d, std::size_t capacity, Visit&& visit) const {
  CANOPY_CHECK(map_ != nullptr, "VoxelIndex::walk before rebuild");
  // As cast(): float end points, the same walk, the same capacity.
  const octomap::point3d origin(float(origin_d.x()), float(origin_d.y()), float(origin_d.z()));
  const octomap::point3d end(float(end_d.x()), float(end_d.y()), float(end_d.z()));
  if (capacity == 0) {
    octomap::OcTreeKey k;
    return map_->coordToKeyChecked(origin, k) && map_->coordToKeyChecked(end, k);
  }
  std::size_t n = 0;
  bool have_brick = false;
  std::uint64_t cached_bk = 0;
  const std::uint32_t* cached = nullptr;
  bool dropped = false;
  return mapping::walk_ray(*map_, origin, end, [&](unsigned x, unsigned y, unsigned z) {
    const std::uint64_t bk = mapping::brick_key(x, y, z);
    if (!have_brick || bk != cached_bk) {
      have_brick = true;
      cached_bk = bk;
      cached = brick(bk);
      dropped = !cached && dropped_x(x >> kBrickBits);
    }
    if (!visit(palette_[cached ? cached[mapping::brick_cell(x, y, z)] : dropped ? map_id(x, y, z) : 0u])) return false;
    return ++n < capacity;
  });
}

/// The slow reference traversal: OctoMap's computeRayKeys, then one tree search per key.
/// Appends (key, state or nullptr) pairs; false when an end is outside the tree.
struct ReferenceVoxel {
  octomap::OcTreeKey key;
  const mapping::SemanticState* state = nullptr;
};
bool cast_reference(const mapping::SemanticOcTree& map, const Vec3& origin, const Vec3& end,
                    octomap::KeyRay* scratch, std::vector<ReferenceVoxel>* out);

}  // namespace canopy::nbv
