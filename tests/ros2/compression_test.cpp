// Chunk compression: each kind round-trips, and corrupt data, a wrong declared size or a
// decompression bomb is InputError, never a write past the declared size.
#include "canopy/ros2/compression.h"

#include <gtest/gtest.h>

#include <random>

#include "canopy/common/error.h"

namespace canopy::ros2 {
namespace {

std::string sample(std::size_t n) {
  std::string s(n, '\0');
  std::mt19937 rng(4);
  for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<char>((i % 251 < 200) ? (i / 7) & 0xFF : rng() & 0xFF);
  return s;
}

TEST(Compression, NamesRoundTrip) {
  for (Compression c : {Compression::kNone, Compression::kLz4, Compression::kZstd})
    EXPECT_EQ(parse_compression(compression_name(c)), c);
  EXPECT_FALSE(parse_compression("bz2"));
  EXPECT_FALSE(parse_compression("LZ4"));
}

TEST(Compression, EveryKindRoundTrips) {
  Decompressor d;
  for (Compression c : {Compression::kNone, Compression::kLz4, Compression::kZstd}) {
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(1000), std::size_t(300000)}) {
      Compressor comp(c);
      const std::string in = sample(n);
      std::string packed;
      comp.compress(in, packed);
      if (c != Compression::kNone && n > 1000) {
        EXPECT_LT(packed.size(), in.size()) << compression_name(c);
      }
      std::string out(n, '\0');
      d.decompress(c, packed, out.data(), out.size());
      EXPECT_EQ(out, in) << compression_name(c) << " " << n;
    }
  }
}

TEST(Compression, WrongSizesAreRefused) {
  Decompressor d;
  for (Compression c : {Compression::kNone, Compression::kLz4, Compression::kZstd}) {
    Compressor comp(c);
    const std::string in = sample(5000);
    std::string packed;
    comp.compress(in, packed);
    std::string small(4999, '\0');
    EXPECT_THROW(d.decompress(c, packed, small.data(), small.size()), InputError) << compression_name(c);
    std::string big(5001, '\0');
    EXPECT_THROW(d.decompress(c, packed, big.data(), big.size()), InputError) << compression_name(c);
    // The context is usable again after an error.
    std::string right(5000, '\0');
    d.decompress(c, packed, right.data(), right.size());
    EXPECT_EQ(right, in);
  }
}

TEST(Compression, ABombDeclaredSmallIsRefused) {
  // 64 MiB of zeros compress to a few KiB; declared as 1 KiB they are refused.
  const std::string zeros(std::size_t(64) << 20, '\0');
  Decompressor d;
  for (Compression c : {Compression::kLz4, Compression::kZstd}) {
    Compressor comp(c);
    std::string packed;
    comp.compress(zeros, packed);
    EXPECT_LT(packed.size(), std::size_t(1) << 20);
    std::string out(1024, '\0');
    EXPECT_THROW(d.decompress(c, packed, out.data(), out.size()), InputError) << compression_name(c);
  }
}

TEST(Compression, CorruptOrCutDataIsRefused) {
  Decompressor d;
  for (Compression c : {Compression::kLz4, Compression::kZstd}) {
    Compressor comp(c);
    const std::string in = sample(20000);
    std::string packed;
    comp.compress(in, packed);
    std::string out(in.size(), '\0');
    for (std::size_t cut = 0; cut < packed.size(); cut += 97)
      EXPECT_THROW(d.decompress(c, std::string_view(packed).substr(0, cut), out.data(), out.size()), InputError)
          << compression_name(c) << " cut at " << cut;
    // Flipped bytes: refused or, where the format cannot tell, a different result of the right
    // size (the chunk CRC catches those); never a crash.
    std::mt19937 rng(11);
    for (int i = 0; i < 200; ++i) {
      std::string bad = packed;
      bad[rng() % bad.size()] ^= static_cast<char>(1 + rng() % 255);
      try {
        d.decompress(c, bad, out.data(), out.size());
      } catch (const InputError&) {
      }
    }
  }
}

}  // namespace
}  // namespace canopy::ros2
