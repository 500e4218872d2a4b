#pragma once
// LSD radix sort of 64-bit values (the scan inserter's voxel codes, the truth's voxel keys).
// Passes whose byte is the same in every value are skipped, so sorting codes of a small region
// costs few passes.

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

namespace canopy {

/// Sorts `v` ascending (stably) by its low `bits` bits; higher bits ride along unsorted;
/// `tmp` is scratch.
inline void radix_sort_u64(std::vector<std::uint64_t>& v, std::vector<std::uint64_t>& tmp, int bits = 64) {
  const std::size_t n = v.size();
  if (n < 2) return;
  const int passes = (bits + 7) / 8;
  std::vector<std::array<std::uint32_t, 256>> hist(static_cast<std::size_t>(passes));
  for (auto& h : hist) h.fill(0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t x = v[i];
    for (int p = 0; p < passes; ++p) ++hist[static_cast<std::size_t>(p)][(x >> (8 * p)) & 0xff];
  }
  tmp.resize(n);
  std::uint64_t* src = v.data();
  std::uint64_t* dst = tmp.data();
  for (int p = 0; p < passes; ++p) {
    auto& h = hist[static_cast<std::size_t>(p)];
    const int shift = 8 * p;
    if (h[(src[0] >> shift) & 0xff] == n) continue;  // every value has the same byte here
    std::uint32_t sum = 0;
    for (auto& c : h) {
      const std::uint32_t t = c;
      c = sum;
      sum += t;
    }
    for (std::size_t i = 0; i < n; ++i) dst[h[(src[i] >> shift) & 0xff]++] = src[i];
    std::swap(src, dst);
  }
  if (src != v.data()) std::memcpy(v.data(), src, n * sizeof(std::uint64_t));
}

}  // namespace canopy
