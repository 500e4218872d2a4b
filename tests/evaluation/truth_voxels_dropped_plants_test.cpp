// A world generated with its plants dropped (issue 49: a long world holds a plant's parts only
// while it is used) gives every consumer of the plants the answers of the world that holds
// them: the truth's voxels (whole and per window) and the colour check of its materials.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <limits>
#include <random>
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

namespace canopy::evaluation {
namespace {

// A plant's surface keys computed four samples at a time in AVX2 lanes (where the processor
// has them) and gathered in a bit grid over the plant's box are the reference's (scalar samples,
// every key sorted), key for key: on the dense preset's plants at the mission's resolution
// (1 cm) and an odd one, and on random triangles from a tenth of a voxel to forty voxels long,
// some far out (the scalar code's, and keys outside any box) and some degenerate.
TEST(TruthVoxels, VectorisedSurfaceKeysAreTheScalarOnes) {
  world::WorldSpec spec = world::WorldSpec::load("worlds/dense.yaml");
  spec.rows.plants_per_row = 1;
  const world::World w = world::generate_world(spec);
  ASSERT_FALSE(w.plants.empty());
  for (const double res : {0.01, 0.0037}) {
    for (const auto& plant : w.plants) {
      const std::vector<std::uint64_t> scalar = plant_surface_keys(plant, res, false);
      EXPECT_GT(scalar.size(), 10000u);
      EXPECT_TRUE(plant_surface_keys(plant, res, true) == scalar) << "plant " << plant.index << ", res " << res;
    }
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.001, 0.4);
  // Every third triangle's vertices on a grid of a quarter voxel: samples on voxel faces, where
  // a rounding of its own (a reciprocal, another order of sums) would give other keys.
  const auto snap = [&](const Vec3& p, int t) { return t % 3 == 0 ? Vec3((p / 0.0025).array().round() * 0.0025) : p; };
  const auto random_part = [&](double far_m) {
    world::PlantPart part;
    for (int t = 0; t < 1500; ++t) {
      const Vec3 a = snap(Vec3(unit(rng) * (t % 100 == 0 ? far_m : 2.0), unit(rng), unit(rng)), t);
      const double s = size(rng);
      const Vec3 b = snap(a + s * Vec3(unit(rng), unit(rng), unit(rng)), t);
      const Vec3 c = t % 50 == 0 ? b : snap(a + s * Vec3(unit(rng), unit(rng), unit(rng)), t);
      const int base = static_cast<int>(part.mesh.vertices.size());
      part.mesh.vertices.insert(part.mesh.vertices.end(), {a, b, c});
      part.mesh.faces.push_back({base, base + 1, base + 2});
    }
    return part;
  };
  world::Plant odd;  // a box of 45 M cells: the bit grid's
  odd.parts = {random_part(2.0), random_part(2.0)};
  world::Plant far = odd;  // a box too large: every key sorted, some far out of the lanes' reach
  far.parts.push_back(random_part(1e7));
  for (const world::Plant* plant : {&odd, &far}) {
    const std::vector<std::uint64_t> scalar = plant_surface_keys(*plant, 0.01, false);
    EXPECT_GT(scalar.size(), 100000u);
    EXPECT_TRUE(plant_surface_keys(*plant, 0.01, true) == scalar) << (plant == &far ? "far" : "odd");
    EXPECT_TRUE(std::is_sorted(scalar.begin(), scalar.end()));
    EXPECT_TRUE(std::adjacent_find(scalar.begin(), scalar.end()) == scalar.end());
  }
}

}  // namespace
}  // namespace canopy::evaluation
