// A world generated with its plants dropped (issue 49: a long world holds a plant's parts only
// while it is used) gives every consumer of the plants the answers of the world that holds
// them: the truth's voxels (whole and per window) and the colour check of its materials.

#include <gtest/gtest.h>

#include "canopy/evaluation/segmentation_check.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/world/world.h"

namespace canopy::evaluation {
namespace {

world::World dropped_world(const world::WorldSpec& spec) {
  world::GenerateOptions drop;
  drop.drop_plants_from_triangles = 0.0;
  return world::generate_world(spec, drop);
}

TEST(DroppedPlants, TheTruthVoxelsAndTheColourCheckAreTheHeldWorlds) {
  world::WorldSpec spec;
  spec.rows.plants_per_row = 3;
  const world::World held = world::generate_world(spec), dropped = dropped_world(spec);
  ASSERT_TRUE(held.plants_held());
  ASSERT_FALSE(dropped.plants_held());
  for (const auto& [from, to] : {std::pair{-1e9, 1e9}, std::pair{0.2, 0.9}}) {
    const std::vector<Vec3> want = world_occupied_voxels(held, 0.02, from, to);
    EXPECT_GT(want.size(), 1000u);
    EXPECT_TRUE(world_occupied_voxels(dropped, 0.02, from, to) == want) << "plants from " << from;
  }
  const std::vector<MaterialSegmentation> a = check_color_segmentation(held, {}), b = check_color_segmentation(dropped, {});
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GT(a.size(), 3u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].owner, b[i].owner);
    EXPECT_EQ(a[i].material, b[i].material);
    EXPECT_EQ(a[i].class_name, b[i].class_name);
    EXPECT_EQ(a[i].share, b[i].share) << a[i].material;  // exact: the same parts, the same sums
    EXPECT_EQ(a[i].problem, b[i].problem);
  }
}

}  // namespace
}  // namespace canopy::evaluation
