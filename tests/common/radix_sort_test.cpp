// The LSD radix sort against std::sort: random values over the full 64 bits and over a few low
// bits (the passes whose byte never changes are skipped), duplicates, and a partial key width
// (values ordered by their low bits only, stably).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "canopy/common/radix_sort.h"

namespace canopy {
namespace {

TEST(RadixSort, SortsAsStdSort) {
  std::mt19937_64 rng(5);
  std::vector<std::uint64_t> tmp;
  for (const std::uint64_t mask : {~std::uint64_t{0}, std::uint64_t{0xffff}, std::uint64_t{0xff00ff0000}, std::uint64_t{0}}) {
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{1000}, std::size_t{100000}}) {
      std::vector<std::uint64_t> v(n);
      for (auto& x : v) x = rng() & mask;
      std::vector<std::uint64_t> want = v;
      std::sort(want.begin(), want.end());
      radix_sort_u64(v, tmp);
      EXPECT_EQ(v, want) << "mask " << mask << " n " << n;
    }
  }
}

TEST(RadixSort, LowBitsOnlyKeepTheOrderOfEqualKeys) {
  std::mt19937_64 rng(6);
  std::vector<std::uint64_t> v(20000), tmp;
  for (auto& x : v) x = rng();
  std::vector<std::uint64_t> want = v;
  std::stable_sort(want.begin(), want.end(), [](std::uint64_t a, std::uint64_t b) { return (a & 0xffffff) < (b & 0xffffff); });
  radix_sort_u64(v, tmp, 24);
  EXPECT_EQ(v, want);
}

}  // namespace
}  // namespace canopy
