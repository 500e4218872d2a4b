#pragma once
// A byte of flags per voxel for a sparse set of voxels, addressed by Morton code
// (mapping::morton_code), kept in the project's bricks of 8 x 8 x 8 voxels (mapping/voxel_key.h).
// In Morton order a brick is the run of 512 codes that share all but their last 9 bits, so a
// brick is found by the code shifted, not by mapping::brick_key (which would decode the code
// first). A scan's voxel updates come sorted by Morton code, so looking them up one after
// another mostly stays in the brick looked up last, which is remembered: one hash lookup per
// brick instead of one per voxel. (Looking voxels up in a hash of
// every fruit voxel was about 40 % of the evaluator's time on a 200-plant row, its lookups
// missing the caches: docs/performance.md.)
//
// A voxel absent from the set reads 0; setting 0 removes it, and a brick with no voxel left is
// freed. Not safe for concurrent readers: get() remembers the brick it read.

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>

#include "canopy/mapping/voxel_key.h"

namespace canopy::evaluation {

class BrickFlags {
 public:
  /// The flags of the voxel with Morton code `code` (0: not in the set).
  std::uint8_t get(std::uint64_t code) const {
    const Brick* b = find(code >> kShift);
    return b ? b->flags[code & kMask] : 0;
  }
  /// Sets the voxel's flags; 0 removes it from the set.
  void set(std::uint64_t code, std::uint8_t flags) {
    const std::uint64_t key = code >> kShift;
    Brick* b = const_cast<Brick*>(find(key));
    if (!b) {
      if (!flags) return;
      b = &bricks_[key];
      last_ = b;
    }
    std::uint8_t& f = b->flags[code & kMask];
    if (!f && flags) {
      ++b->count;
      ++size_;
    } else if (f && !flags) {
      --b->count;
      --size_;
    }
    f = flags;
    if (b->count == 0) {
      bricks_.erase(key);
      last_ = nullptr;  // still the answer for `key`
    }
  }
  /// Voxels in the set.
  std::size_t size() const { return size_; }
  /// Bricks holding them.
  std::size_t bricks() const { return bricks_.size(); }
  void clear() {
    bricks_.clear();
    size_ = 0;
    last_key_ = kNone;
    last_ = nullptr;
  }
  /// Bytes held: the bricks, each in a hash node (its key and link), and the buckets.
  std::size_t memory_bytes() const {
    return bricks_.size() * (sizeof(Brick) + sizeof(std::uint64_t) + sizeof(void*)) + bricks_.bucket_count() * sizeof(void*);
  }

 private:
  static constexpr unsigned kShift = 3 * mapping::kBrickBits;  // a brick's cells in the code's low bits
  static constexpr std::uint64_t kMask = (std::uint64_t(1) << kShift) - 1;
  static_assert(mapping::kBrickCells == int(kMask + 1), "a brick is the run of codes kShift spans");
  static constexpr std::uint64_t kNone = ~std::uint64_t(0);  // no Morton code shifted by kShift
  struct Brick {
    std::array<std::uint8_t, mapping::kBrickCells> flags{};
    std::uint16_t count = 0;  // non-zero flags
  };
  const Brick* find(std::uint64_t key) const {
    if (key != last_key_) {
      const auto it = bricks_.find(key);
      last_key_ = key;
      last_ = it == bricks_.end() ? nullptr : &it->second;
    }
    return last_;
  }

  std::unordered_map<std::uint64_t, Brick> bricks_;  // nodes: a brick's address holds while it exists
  std::size_t size_ = 0;
  mutable std::uint64_t last_key_ = kNone;  // the brick find() looked up last, and what it found
  mutable const Brick* last_ = nullptr;
};

}  // namespace canopy::evaluation
