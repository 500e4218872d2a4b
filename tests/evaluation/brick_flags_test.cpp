// BrickFlags against a hash of every voxel (the container it replaced): the same answers after
// every step of a long random sequence of sets and reads, clustered and scattered, in Morton
// order and not.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include "canopy/evaluation/brick_flags.h"
#include "canopy/mapping/voxel_key.h"

using canopy::evaluation::BrickFlags;

namespace {

std::uint8_t reference_get(const std::unordered_map<std::uint64_t, std::uint8_t>& m, std::uint64_t code) {
  const auto it = m.find(code);
  return it == m.end() ? 0 : it->second;
}

}  // namespace

TEST(BrickFlags, AgreesWithAHashOfEveryVoxel) {
  std::mt19937_64 rng(7);
  BrickFlags flags;
  std::unordered_map<std::uint64_t, std::uint8_t> ref;
  // Codes around a few centres (runs inside a brick and across its edges) and scattered ones.
  const std::vector<std::uint64_t> centres = {0, 511, 512, 1u << 20, (std::uint64_t(1) << 47) - 300};
  std::uniform_int_distribution<int> offset(-700, 700), pick(0, int(centres.size())), value(0, 3);
  std::uniform_int_distribution<std::uint64_t> anywhere(0, (std::uint64_t(1) << 48) - 1);
  const auto draw = [&] {
    const int c = pick(rng);
    if (c == int(centres.size())) return anywhere(rng);
    const std::int64_t v = std::int64_t(centres[c]) + offset(rng);
    return std::uint64_t(std::max<std::int64_t>(v, 0));
  };
  std::size_t removed_bricks = 0;
  for (int round = 0; round < 200; ++round) {
    std::vector<std::uint64_t> batch(300);
    for (auto& code : batch) code = draw();
    if (round % 2 == 0) std::sort(batch.begin(), batch.end());  // as a scan's updates come
    for (std::uint64_t code : batch) {
      ASSERT_EQ(flags.get(code), reference_get(ref, code)) << "read before set, code " << code;
      // Mostly clearing late in the run, so bricks empty and are freed.
      const std::uint8_t f = round > 120 && value(rng) != 0 ? 0 : std::uint8_t(value(rng) * 5);
      const std::size_t bricks = flags.bricks();
      flags.set(code, f);
      if (flags.bricks() < bricks) ++removed_bricks;
      if (f) ref[code] = f;
      else ref.erase(code);
      ASSERT_EQ(flags.get(code), f);
      ASSERT_EQ(flags.size(), ref.size());
    }
    for (std::uint64_t code : batch) ASSERT_EQ(flags.get(code), reference_get(ref, code));
  }
  for (const auto& [code, f] : ref) ASSERT_EQ(flags.get(code), f);
  EXPECT_GT(removed_bricks, 0u);  // the run did free bricks
  EXPECT_GT(flags.size(), 0u);
  flags.clear();
  EXPECT_EQ(flags.size(), 0u);
  EXPECT_EQ(flags.bricks(), 0u);
  for (const auto& [code, f] : ref) ASSERT_EQ(flags.get(code), 0);
}

TEST(BrickFlags, ABrickIsTheRunOf512CodesSharingTheirHighBits) {
  BrickFlags flags;
  flags.set(512, 1);
  flags.set(1023, 2);
  EXPECT_EQ(flags.bricks(), 1u);
  flags.set(1024, 3);
  flags.set(511, 4);
  EXPECT_EQ(flags.bricks(), 3u);
  flags.set(512, 0);
  flags.set(1023, 0);
  EXPECT_EQ(flags.bricks(), 2u);  // emptied, freed
  EXPECT_EQ(flags.get(512), 0);
  EXPECT_EQ(flags.get(1024), 3);
  EXPECT_EQ(flags.get(511), 4);
  EXPECT_EQ(flags.size(), 2u);
}

TEST(BrickFlags, ItsBricksAreTheVoxelIndexsBricks) {
  // Every voxel of one mapping::brick_key, and only those, share a brick here: filling the 512
  // voxels of a brick (and one voxel of each neighbour) makes one brick per brick_key.
  BrickFlags flags;
  const unsigned bx = 4097, by = 123, bz = 77;  // brick coordinates
  for (unsigned z = 0; z < 8; ++z)
    for (unsigned y = 0; y < 8; ++y)
      for (unsigned x = 0; x < 8; ++x) {
        const octomap::OcTreeKey k(octomap::key_type(bx * 8 + x), octomap::key_type(by * 8 + y), octomap::key_type(bz * 8 + z));
        ASSERT_EQ(canopy::mapping::brick_key(k), canopy::mapping::brick_key_of_brick(bx, by, bz));
        flags.set(canopy::mapping::morton_code(k), 1);
      }
  EXPECT_EQ(flags.bricks(), 1u);
  EXPECT_EQ(flags.size(), 512u);
  const octomap::OcTreeKey past(octomap::key_type(bx * 8 + 8), octomap::key_type(by * 8), octomap::key_type(bz * 8));
  const octomap::OcTreeKey before(octomap::key_type(bx * 8), octomap::key_type(by * 8 - 1), octomap::key_type(bz * 8));
  flags.set(canopy::mapping::morton_code(past), 2);
  flags.set(canopy::mapping::morton_code(before), 3);
  EXPECT_EQ(flags.bricks(), 3u);
}
