#include <gtest/gtest.h>

#include <cmath>

#include "canopy/perception/segmentation_noise.h"

using namespace canopy;
using namespace canopy::perception;

namespace {
// A grid of square masks alternating fruit (2) and leaf (1) on background.
Image<std::uint8_t> masks_image(int* n_masks) {
  Image<std::uint8_t> img(100, 100, 0);
  int n = 0;
  for (int by = 0; by < 10; ++by)
    for (int bx = 0; bx < 10; ++bx) {
      ++n;
      for (int y = by * 10 + 1; y < by * 10 + 9; ++y)
        for (int x = bx * 10 + 1; x < bx * 10 + 9; ++x) img.at(x, y) = static_cast<std::uint8_t>(1 + (bx + by) % 2);
    }
  *n_masks = n;
  return img;
}
}  // namespace

TEST(SegmentationNoise, MasksAreConnectedRegions) {
  int n = 0;
  const Image<std::uint8_t> img = masks_image(&n);
  Image<std::int32_t> m;
  EXPECT_EQ(label_masks(img, Image<std::int32_t>(), &m), n);
  // Instances split one class region in two.
  Image<std::uint8_t> two(4, 1, 2);
  Image<std::int32_t> inst(4, 1, 0);
  inst.at(2, 0) = inst.at(3, 0) = 1;
  EXPECT_EQ(label_masks(two, inst, &m), 2);
  EXPECT_EQ(label_masks(two, Image<std::int32_t>(), &m), 1);
}

TEST(SegmentationNoise, PgtOneIsNoNoise) {
  int n = 0;
  const Image<std::uint8_t> img = masks_image(&n);
  Image<std::uint8_t> noisy = img;
  Rng rng(5);
  const MaskNoiseStats s = apply_mask_noise(noisy, Image<std::int32_t>(), 3, 1.0, rng);
  EXPECT_EQ(noisy.data, img.data);
  EXPECT_EQ(s.flipped, 0u);
}

// P_gt = 0.7: the share of flipped masks over many images is 0.3 within 4 sigma, and the
// wrong class is split evenly between the two other classes (0.15 each).
TEST(SegmentationNoise, PgtPointSevenFlipsTheExpectedShare) {
  int n = 0;
  const Image<std::uint8_t> img = masks_image(&n);
  Rng rng(12345);
  std::size_t masks = 0, flipped = 0, to_background = 0, fruit_to_leaf = 0, fruit_masks = 0;
  for (int image = 0; image < 200; ++image) {
    Image<std::uint8_t> noisy = img;
    const MaskNoiseStats s = apply_mask_noise(noisy, Image<std::int32_t>(), 3, 0.7, rng);
    masks += s.masks;
    flipped += s.flipped;
    for (int by = 0; by < 10; ++by)
      for (int bx = 0; bx < 10; ++bx) {
        const int x = bx * 10 + 4, y = by * 10 + 4;
        const int before = img.at(x, y), after = noisy.at(x, y);
        // A mask is uniform after noise.
        EXPECT_EQ(noisy.at(bx * 10 + 1, by * 10 + 1), after);
        to_background += after == 0;
        if (before == 2) {
          ++fruit_masks;
          fruit_to_leaf += after == 1;
        }
      }
    EXPECT_EQ(noisy.at(0, 0), 0);  // background is not a mask
  }
  ASSERT_EQ(masks, 200u * 100u);
  const double share = double(flipped) / double(masks);
  const double sigma = std::sqrt(0.3 * 0.7 / double(masks));
  EXPECT_NEAR(share, 0.3, 4 * sigma);
  EXPECT_NEAR(double(to_background) / double(masks), 0.15, 4 * std::sqrt(0.15 * 0.85 / double(masks)));
  EXPECT_NEAR(double(fruit_to_leaf) / double(fruit_masks), 0.15,
              4 * std::sqrt(0.15 * 0.85 / double(fruit_masks)));
}
