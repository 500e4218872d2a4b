// The ground truth of a world (world/ground_truth.h): surface points on the fruits at the
// requested density, and the saved files read back to the same doubles.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/world/world.h"

namespace canopy::world {
namespace {

// The small world (two plants) with another seed.
World small_world(std::uint64_t seed) {
  WorldSpec spec = WorldSpec::load(find_data_file("worlds/small.yaml"));
  spec.seed = seed;
  return generate_world(spec);
}

TEST(GroundTruth, PointsLieOnFruitsWithTheRequestedDensity) {
  const World w = small_world(3);
  ASSERT_FALSE(w.truth.fruits.empty());
  for (const auto& f : w.truth.fruits) {
    const double expected = f.surface_area_m2 / (w.truth.point_spacing_m * w.truth.point_spacing_m);
    EXPECT_NEAR(static_cast<double>(f.surface_points.size()), expected, 4.0 * std::sqrt(expected) + 5.0);
    for (const auto& p : f.surface_points) {
      EXPECT_TRUE((p.array() >= f.bbox_min.array() - 1e-9).all() && (p.array() <= f.bbox_max.array() + 1e-9).all());
    }
  }
}

TEST(GroundTruth, SaveLoadRoundTrip) {
  const World w = small_world(4);
  const std::string dir = testing::TempDir() + "/gt_roundtrip";
  std::filesystem::create_directories(dir);
  w.truth.save(dir);
  const GroundTruth back = GroundTruth::load(dir);
  ASSERT_EQ(back.fruits.size(), w.truth.fruits.size());
  for (size_t i = 0; i < back.fruits.size(); ++i) {
    EXPECT_EQ(back.fruits[i].instance_id, w.truth.fruits[i].instance_id);
    EXPECT_EQ(back.fruits[i].surface_points, w.truth.fruits[i].surface_points);  // %.17g is exact
    EXPECT_EQ(back.fruits[i].bbox_min, w.truth.fruits[i].bbox_min);
    EXPECT_EQ(back.fruits[i].target, w.truth.fruits[i].target);
  }
  std::ofstream(dir + "/fruit_points.csv") << "instance_id,x,y,z\n0,1,2\n";
  EXPECT_THROW(GroundTruth::load(dir), InputError);
}

}  // namespace
}  // namespace canopy::world
