#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/png_io.h"

namespace canopy {
namespace {

TEST(PngIo, PngRoundTrips) {
  const std::string dir = testing::TempDir();
  Image<Rgb8> rgb(5, 3);
  Image<std::uint16_t> g(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      rgb.at(x, y) = Rgb8{static_cast<std::uint8_t>(x * 40), static_cast<std::uint8_t>(y * 70), 9};
      g.at(x, y) = static_cast<std::uint16_t>(x * 1000 + y * 17 + 60000 * (x == 4));
    }
  write_png(dir + "/a.png", rgb);
  write_png_gray16(dir + "/b.png", g);
  EXPECT_EQ(read_png_rgb(dir + "/a.png").data, rgb.data);
  EXPECT_EQ(read_png_gray16(dir + "/b.png").data, g.data);
  write_file_atomic(dir + "/c.png", "not a png");
  EXPECT_THROW(read_png_rgb(dir + "/c.png"), InputError);
}

// A header claiming an absurd size is refused before any pixel memory is allocated.
TEST(PngIo, RefusesAbsurdHeaderSizes) {
  // A PNG whose header claims 100000 x 100000 16-bit pixels (signature, IHDR, a token IDAT, IEND).
  const unsigned char png[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
                               0x44, 0x52, 0x00, 0x01, 0x86, 0xa0, 0x00, 0x01, 0x86, 0xa0, 0x10, 0x00, 0x00, 0x00,
                               0x00, 0xdd, 0xa9, 0x88, 0x57, 0x00, 0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78,
                               0x9c, 0x63, 0x60, 0x80, 0x00, 0x00, 0x00, 0x08, 0x00, 0x01, 0xb7, 0x58, 0x73, 0x95,
                               0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  const std::string path = testing::TempDir() + "/huge_header.png";
  write_file_atomic(path, std::string(reinterpret_cast<const char*>(png), sizeof png));
  try {
    read_png_gray16(path);
    FAIL() << "a 100000 x 100000 header was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("100000 x 100000"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace canopy
