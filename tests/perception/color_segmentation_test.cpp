#include <gtest/gtest.h>

#include "canopy/common/error.h"
#include "canopy/perception/color_segmentation.h"

using namespace canopy;
using namespace canopy::perception;

TEST(ColorSegmentation, HsvMatchesOpenCvConvention) {
  Hsv red = rgb_to_hsv({255, 0, 0});
  EXPECT_EQ(red.h, 0);
  EXPECT_EQ(red.s, 255);
  EXPECT_EQ(red.v, 255);
  EXPECT_EQ(rgb_to_hsv({0, 255, 0}).h, 60);
  EXPECT_EQ(rgb_to_hsv({0, 0, 255}).h, 120);
  EXPECT_EQ(rgb_to_hsv({255, 255, 0}).h, 30);
  EXPECT_EQ(rgb_to_hsv({255, 0, 128}).h, 165);  // 330 degrees
  Hsv grey = rgb_to_hsv({100, 100, 100});
  EXPECT_EQ(grey.s, 0);
  EXPECT_EQ(grey.v, 100);
}

TEST(ColorSegmentation, DefaultBandsLabelFruitLeafBackground) {
  const SemanticClasses classes;
  Image<Rgb8> img(6, 1);
  img.at(0, 0) = {200, 30, 30};   // red fruit
  img.at(1, 0) = {220, 200, 20};  // yellow fruit
  img.at(2, 0) = {40, 160, 40};   // leaf
  img.at(3, 0) = {90, 90, 90};    // grey background
  img.at(4, 0) = {230, 20, 120};  // magenta-red (H ~ 163): fruit
  img.at(5, 0) = {20, 20, 200};   // blue background
  const Image<std::uint8_t> l = segment_by_color(img, ColorSegmentationParams{}, classes);
  const int fruit = classes.index_of("fruit"), leaf = classes.index_of("leaf");
  EXPECT_EQ(l.at(0, 0), fruit);
  EXPECT_EQ(l.at(1, 0), fruit);
  EXPECT_EQ(l.at(2, 0), leaf);
  EXPECT_EQ(l.at(3, 0), 0);
  EXPECT_EQ(l.at(4, 0), fruit);
  EXPECT_EQ(l.at(5, 0), 0);
}

TEST(ColorSegmentation, UnknownClassInBandIsAnInputError) {
  ColorSegmentationParams p;
  p.bands[0].class_name = "stem";
  EXPECT_THROW(segment_by_color(Image<Rgb8>(2, 2), p, SemanticClasses{}), InputError);
}
