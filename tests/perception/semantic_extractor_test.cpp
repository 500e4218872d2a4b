#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/perception/semantic_extractor.h"

using namespace canopy;
using namespace canopy::perception;

namespace {
LabelledFrame flat_frame(float depth) {
  LabelledFrame f;
  f.intrinsics.width_px = f.intrinsics.height_px = 40;
  f.intrinsics.fx_px = f.intrinsics.fy_px = 38.136;
  f.intrinsics.cx_px = f.intrinsics.cy_px = 20;
  f.rgb = Image<Rgb8>(40, 40, Rgb8{200, 30, 30});
  f.depth_m = Image<float>(40, 40, depth);
  f.class_id = Image<std::uint8_t>(40, 40, 2);
  f.instance = Image<std::int32_t>(40, 40, 3);
  f.T_world_camera = Pose::Identity();
  f.T_world_camera.translation() = Vec3(1, 2, 3);
  return f;
}
}  // namespace

TEST(SemanticExtractor, UnprojectsIntoTheWorldFrame) {
  const LabelledFrame f = flat_frame(0.5f);
  ExtractorParams p;
  p.p_gt = 1.0;
  SemanticExtractor ex(p, SemanticClasses{});
  const LabelledCloud c = ex.extract(f);
  ASSERT_EQ(c.size(), 1600u);
  EXPECT_EQ(c.origin_world, Vec3(1, 2, 3));
  // Pixel (0, 0) centre at (0.5, 0.5).
  const Vec3 expected = Vec3(1, 2, 3) + f.intrinsics.unproject(0.5, 0.5, 0.5);
  EXPECT_NEAR((c.points_world[0].cast<double>() - expected).norm(), 0.0, 1e-6);
  for (std::uint8_t l : c.labels) EXPECT_EQ(l, 2);
}

TEST(SemanticExtractor, BadDepthsAndLabelsAreSkippedAndCounted) {
  LabelledFrame f = flat_frame(0.5f);
  f.depth_m.at(0, 0) = std::numeric_limits<float>::quiet_NaN();
  f.depth_m.at(1, 0) = std::numeric_limits<float>::infinity();
  f.depth_m.at(2, 0) = 0.f;
  f.depth_m.at(3, 0) = -1.f;
  f.depth_m.at(4, 0) = 5.f;  // beyond the camera's max range
  f.class_id.at(5, 0) = 9;   // not a class
  ExtractorParams p;
  p.source = LabelSource::kTruth;
  p.p_gt = 1.0;
  p.missing_depth = MissingDepth::kSkip;
  SemanticExtractor ex(p, SemanticClasses{});
  const LabelledCloud c = ex.extract(f);
  EXPECT_EQ(c.stats.bad_depth, 4u);
  EXPECT_EQ(c.stats.missing_depth, 0u);
  EXPECT_EQ(c.stats.out_of_range, 1u);
  EXPECT_EQ(c.stats.bad_label, 1u);
  EXPECT_EQ(c.size(), 1600u - 6u);
  EXPECT_EQ(c.stats.pixels, 1600u);
  // carve (the default): NaN, inf and 0 are "no return" and become points at 3.0 m labelled
  // background; a negative depth stays bad data.
  p.missing_depth = MissingDepth::kCarve;
  SemanticExtractor carve(p, SemanticClasses{});
  const LabelledCloud d = carve.extract(f);
  EXPECT_EQ(d.stats.bad_depth, 1u);
  EXPECT_EQ(d.stats.missing_depth, 3u);
  EXPECT_EQ(d.stats.out_of_range, 1u);
  EXPECT_EQ(d.size(), 1600u - 3u);
  const Vec3 far = (d.points_world[0].cast<double>() - f.T_world_camera.translation());
  EXPECT_NEAR((f.T_world_camera.linear().transpose() * far).z(), 3.0, 1e-5);
  EXPECT_EQ(d.labels[0], 0);
}

TEST(SemanticExtractor, TruthModeNeedsLabelsAndNoiseIsSeeded) {
  LabelledFrame f = flat_frame(0.5f);
  ExtractorParams p;
  p.source = LabelSource::kTruth;
  p.p_gt = 0.5;
  p.depth_noise_k = 0.01;
  SemanticExtractor a(p, SemanticClasses{}), b(p, SemanticClasses{});
  for (int i = 0; i < 5; ++i) {
    const LabelledCloud ca = a.extract(f), cb = b.extract(f);
    EXPECT_EQ(ca.labels, cb.labels);
    ASSERT_EQ(ca.size(), cb.size());
    for (std::size_t k = 0; k < ca.size(); ++k) ASSERT_EQ(ca.points_world[k], cb.points_world[k]);
  }
  f.class_id = Image<std::uint8_t>();
  EXPECT_THROW(a.extract(f), InputError);
}
