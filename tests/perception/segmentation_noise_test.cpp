#include <gtest/gtest.h>

#include <cmath>

#include "canopy/common/error.h"
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

// The paper's model: over many images, each class mask (all pixels of a class) keeps its
// class with P_gt = 0.7, becomes each other class with 0.15, and all its pixels move together
// (so a fruit and a leaf region can swap: the mapping is applied once, not in sequence).
TEST(SegmentationNoise, ClassMasksFlipWholeAndAtTheStatedRate) {
  int n = 0;
  const Image<std::uint8_t> img = masks_image(&n);
  Rng rng(777);
  const int images = 4000;
  std::size_t masks = 0, flipped = 0, fruit_kept = 0, fruit_to_leaf = 0, fruit_to_bg = 0, swaps = 0;
  for (int image = 0; image < images; ++image) {
    Image<std::uint8_t> noisy = img;
    const MaskNoiseStats s = apply_class_mask_noise(noisy, 3, 0.7, rng);
    ASSERT_EQ(s.masks, 2u);  // fruit and leaf present; background is not a mask
    masks += s.masks;
    flipped += s.flipped;
    // Every pixel of one true class has one new class.
    int new_of[3] = {-1, -1, -1};
    for (std::size_t i = 0; i < img.data.size(); ++i) {
      int& m = new_of[img.data[i]];
      if (m < 0) m = noisy.data[i];
      ASSERT_EQ(m, noisy.data[i]) << "pixels of class " << int(img.data[i]) << " split in image " << image;
    }
    ASSERT_EQ(new_of[0], 0);
    fruit_kept += new_of[2] == 2;
    fruit_to_leaf += new_of[2] == 1;
    fruit_to_bg += new_of[2] == 0;
    swaps += new_of[2] == 1 && new_of[1] == 2;
  }
  const double N = double(masks);
  EXPECT_NEAR(double(flipped) / N, 0.3, 4 * std::sqrt(0.3 * 0.7 / N));
  const double F = double(images);
  EXPECT_NEAR(double(fruit_kept) / F, 0.7, 4 * std::sqrt(0.7 * 0.3 / F));
  EXPECT_NEAR(double(fruit_to_leaf) / F, 0.15, 4 * std::sqrt(0.15 * 0.85 / F));
  EXPECT_NEAR(double(fruit_to_bg) / F, 0.15, 4 * std::sqrt(0.15 * 0.85 / F));
  // Independent draws per class: fruit->leaf and leaf->fruit together with 0.15^2.
  EXPECT_NEAR(double(swaps) / F, 0.0225, 4 * std::sqrt(0.0225 * 0.9775 / F));
}

// The draws do not depend on the image's content: image n's noise is the same whatever
// classes the earlier images held; P_gt = 1 draws nothing; labels >= K are left alone.
TEST(SegmentationNoise, ClassMaskDrawsIndependentOfContent) {
  Image<std::uint8_t> only_leaf(8, 8, 1), both(8, 8, 1);
  both.at(3, 3) = 2;
  Rng a(9), b(9);
  for (int i = 0; i < 50; ++i) {
    Image<std::uint8_t> x = only_leaf, y = both;
    apply_class_mask_noise(x, 3, 0.5, a);
    apply_class_mask_noise(y, 3, 0.5, b);
    EXPECT_EQ(x.at(0, 0), y.at(0, 0)) << i;  // the leaf mask's fate is the same in both streams
  }
  Rng c(1);
  Image<std::uint8_t> z = both;
  EXPECT_EQ(apply_class_mask_noise(z, 3, 1.0, c).flipped, 0u);
  EXPECT_EQ(z.data, both.data);
  Image<std::uint8_t> bad(2, 1, 7);
  Rng d(3);
  apply_class_mask_noise(bad, 3, 0.0, d);
  EXPECT_EQ(bad.at(0, 0), 7);
  EXPECT_EQ(enum_from_name(kNoiseModelNames, "per_region", "t", "noise model"), NoiseModel::kPerRegion);
  EXPECT_THROW(enum_from_name(kNoiseModelNames, "per_pixel", "t", "noise model"), InputError);
}
