// blit_scaled (row spans, a copy when the sizes match) against the obvious per-pixel rule, for
// random sources, scales, borders and placements reaching past every edge of the target.

#include <gtest/gtest.h>

#include "canopy/common/image.h"
#include "canopy/common/random.h"

namespace canopy {
namespace {

// The rule, one pixel at a time: inside the rectangle the nearest source pixel, in the border
// band the border colour, outside the target nothing.
void blit_reference(const Image<Rgb8>& src, int x0, int y0, int w, int h, Image<Rgb8>* dst, int border, Rgb8 colour) {
  for (int y = y0 - border; y < y0 + h + border; ++y)
    for (int x = x0 - border; x < x0 + w + border; ++x) {
      if (x < 0 || y < 0 || x >= dst->width || y >= dst->height) continue;
      const bool inside = x >= x0 && y >= y0 && x < x0 + w && y < y0 + h;
      dst->at(x, y) = inside ? src.at((x - x0) * src.width / w, (y - y0) * src.height / h) : colour;
    }
}

TEST(BlitScaled, EqualsThePerPixelRuleEverywhere) {
  Rng rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    Image<Rgb8> src(rng.integer(1, 12), rng.integer(1, 12));
    for (Rgb8& p : src.data)
      p = Rgb8{static_cast<std::uint8_t>(rng.integer(0, 255)), static_cast<std::uint8_t>(rng.integer(0, 255)), 7};
    const bool same_size = trial % 3 == 0;
    const int w = same_size ? src.width : rng.integer(1, 20), h = same_size ? src.height : rng.integer(1, 20);
    const int x0 = rng.integer(-25, 30), y0 = rng.integer(-25, 30), border = rng.integer(0, 3);
    const Rgb8 colour{255, 255, 255};
    Image<Rgb8> fast(24, 18, Rgb8{1, 2, 3}), slow = fast;
    blit_scaled(src, x0, y0, w, h, &fast, border, colour);
    blit_reference(src, x0, y0, w, h, &slow, border, colour);
    ASSERT_EQ(fast.data, slow.data) << "trial " << trial << ": " << src.width << "x" << src.height << " -> " << w << "x"
                                    << h << " at " << x0 << "," << y0 << " border " << border;
  }
}

}  // namespace
}  // namespace canopy
