#include "canopy/common/zstd_bytes.h"

#include <gtest/gtest.h>

#include <random>

#include "canopy/common/error.h"

namespace canopy {
namespace {

// Repetitive bytes (as maps are) and random ones, empty and one byte: each comes back exactly.
TEST(ZstdBytes, FramesComeBackAsTheBytes) {
  std::mt19937 rng(3);
  std::string repetitive, random(100000, '\0');
  for (int i = 0; i < 200000; ++i) repetitive += static_cast<char>("canopy"[i % 6] + (i / 5000) % 3);
  for (char& c : random) c = static_cast<char>(rng());
  for (const std::string& bytes : {repetitive, random, std::string(), std::string(1, 'x')})
    for (const int level : {1, 9, 19}) {
      const std::string frame = zstd_compress(bytes, level);
      EXPECT_TRUE(is_zstd_frame(frame));
      EXPECT_EQ(zstd_decompress(frame, "t"), bytes) << bytes.size() << " bytes, level " << level;
    }
  EXPECT_LT(zstd_compress(repetitive, 9).size() * 50, repetitive.size());
  EXPECT_FALSE(is_zstd_frame(repetitive));
  EXPECT_FALSE(is_zstd_frame("\x28\xb5"));
}

// A cut frame, flipped bytes, a frame that hides its size or declares more than allowed: an
// InputError naming the source, never a crash or a short result.
TEST(ZstdBytes, DamagedFramesAreInputErrorsNamingTheSource) {
  std::string bytes;
  for (int i = 0; i < 50000; ++i) bytes += std::to_string(i % 977);
  const std::string frame = zstd_compress(bytes, 9);
  const auto refused = [](const std::string& f, const std::string& what) {
    try {
      zstd_decompress(f, "my.zst");
      return false;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("my.zst"), std::string::npos) << what << ": " << e.what();
      return true;
    }
  };
  EXPECT_TRUE(refused(frame.substr(0, frame.size() - 1), "cut by one"));
  EXPECT_TRUE(refused(frame.substr(0, frame.size() / 2), "cut in half"));
  EXPECT_TRUE(refused(frame.substr(0, 3), "the magic number cut"));
  std::string sizeless = frame;
  sizeless[4] = 0;  // frame header descriptor: no content size
  EXPECT_TRUE(refused(sizeless, "no size"));
  EXPECT_TRUE(refused(std::string("not a frame"), "plain text"));
  try {
    zstd_decompress(frame, "big.zst", bytes.size() - 1);
    FAIL() << "a frame larger than allowed was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("more than"), std::string::npos) << e.what();
  }
  EXPECT_EQ(zstd_decompress(frame, "exact.zst", bytes.size()), bytes);
  // Flipped bytes past the header: refused, or (where a flip only changes literal bytes the
  // frame does not check) bytes of the declared size; never anything else.
  int refused_flips = 0;
  for (std::size_t i = 6; i < frame.size(); i += 1 + frame.size() / 41) {
    std::string bad = frame;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    try {
      EXPECT_EQ(zstd_decompress(bad, "flip").size(), bytes.size());
    } catch (const InputError&) {
      ++refused_flips;
    }
  }
  EXPECT_GT(refused_flips, 5);
}

}  // namespace
}  // namespace canopy
