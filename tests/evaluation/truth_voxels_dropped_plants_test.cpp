// A world generated with its plants dropped (issue 49: a long world holds a plant's parts only
// while it is used) gives every consumer of the plants the answers of the world that holds
// them: the truth's voxels (whole and per window) and the colour check of its materials.

#include <gtest/gtest.h>

#include <iterator>
#include <limits>
#include <utility>

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

// The truth's voxels per window of a long row (the mission's, issue 49), each plant's kept
// while the windows overlap: every window's voxels are world_occupied_voxels', in order; the
// plants held are at most those of the last two windows; an unbounded window keeps none.
TEST(WindowVoxels, EveryWindowIsTheWorldsVoxelsAndTwoWindowsAtMostAreHeld) {
  world::WorldSpec spec;
  spec.rows.plants_per_row = 8;
  const world::World w = dropped_world(spec);
  WindowVoxels windows(w, 0.02);
  const auto plants_in = [&](double from, double to) {
    std::size_t n = 0;
    for (const auto& p : w.plants) n += p.base_position.x() >= from && p.base_position.x() < to;
    return n;
  };
  const std::pair<double, double> asked[] = {{0.0, 1.5}, {0.75, 2.25}, {1.5, 3.0}, {0.0, 1.5}, {0.0, 1.5}, {2.0, 2.0}};
  for (std::size_t i = 0; i < std::size(asked); ++i) {
    const auto [from, to] = asked[i];
    const std::vector<Vec3> want = world_occupied_voxels(w, 0.02, from, to);
    EXPECT_TRUE(windows.voxels(from, to) == want) << "window " << i;
    const std::size_t before = i > 0 ? plants_in(asked[i - 1].first, asked[i - 1].second) : 0;
    EXPECT_LE(windows.plants_held(), plants_in(from, to) + before) << "window " << i;
    EXPECT_GE(windows.plants_held(), plants_in(from, to)) << "window " << i;
  }
  EXPECT_GT(plants_in(0.0, 1.5), 0u);
  EXPECT_GT(world_occupied_voxels(w, 0.02, 0.0, 1.5).size(), 1000u);
  EXPECT_EQ(windows.plants_held(), plants_in(0.0, 1.5));  // the empty window and the one before
  WindowVoxels whole(w, 0.02);
  EXPECT_TRUE(whole.voxels(-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()) ==
              world_occupied_voxels(w, 0.02));
  EXPECT_EQ(whole.plants_held(), 0u);
}

}  // namespace
}  // namespace canopy::evaluation
