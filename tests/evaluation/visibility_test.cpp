// Hemming et al.'s detectability protocol (evaluation/visibility.h) on hand-built scenes.

#include "canopy/evaluation/visibility.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "canopy/world/mesh.h"
#include "canopy/world/world_spec.h"

namespace canopy::evaluation {
namespace {

// A round fruit of radius r centred at c.
world::TriMesh sphere(const Vec3& c, double r) {
  std::vector<Vec2> profile;
  for (int i = 0; i <= 24; ++i) {
    const double a = M_PI * i / 24.0;
    profile.emplace_back(r * std::sin(a), -r * std::cos(a));
  }
  world::TriMesh m = world::make_lobed_revolution(profile, 48, 0, 0.0);
  Pose T = Pose::Identity();
  T.translation() = c;
  m.transform(T);
  return m;
}

// A flat rectangle in the plane y = y0, x in [x0, x1], z in [z0, z1].
world::TriMesh wall(double y0, double x0, double x1, double z0, double z1) {
  world::TriMesh m;
  m.vertices = {Vec3(x0, y0, z0), Vec3(x1, y0, z0), Vec3(x1, y0, z1), Vec3(x0, y0, z1)};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// A world: one fruit at (0, 0.75, 0.5) and a leaf covering the half x < 0 of it from the aisle.
world::World fruit_behind_leaf(bool with_leaf) {
  world::World w;
  w.spec.rows.rows = 1;
  w.spec.rows.row_offset_m = 0.75;
  world::Plant plant;
  plant.index = 0;
  plant.base_position = Vec3(0.0, 0.75, 0.0);
  world::PlantPart fruit;
  fruit.name = "fruit";
  fruit.kind = "fruit";
  fruit.instance_id = 1;
  fruit.fruit_color = "red";
  fruit.mesh = sphere(Vec3(0.0, 0.75, 0.5), 0.04);
  plant.parts.push_back(fruit);
  if (with_leaf) {
    world::PlantPart leaf;
    leaf.name = "leaf";
    leaf.kind = "leaf";
    leaf.mesh = wall(0.65, -0.2, 0.0, 0.3, 0.7);
    plant.parts.push_back(leaf);
  }
  w.plants.push_back(plant);
  w.truth = world::sample_ground_truth(w);
  return w;
}

TEST(Visibility, FruitHalfBehindALeafIsHalfHiddenFromTheFrontAndNotFromTheSide) {
  const world::World w = fruit_behind_leaf(true);
  const RayScene scene(w);
  const int part = scene.part_of_instance(1);
  ASSERT_GE(part, 0);
  const auto& pts = w.truth.fruits.at(0).surface_points;
  ASSERT_GT(pts.size(), 500u);
  const FruitView front = view_fruit(scene, part, pts, Vec3(0.0, 0.25, 0.5));
  // About half of the surface faces a camera 0.5 m away (a bit less: perspective).
  EXPECT_NEAR(double(front.facing_points) / pts.size(), 0.46, 0.04);
  EXPECT_NEAR(front.occlusion(), 0.5, 0.04);
  const FruitView side = view_fruit(scene, part, pts, Vec3(0.5, 0.75, 0.5));
  EXPECT_GT(side.facing_points, 0);
  EXPECT_EQ(side.hidden_points, 0);
}

TEST(Visibility, NothingInFrontHidesNothing) {
  const world::World w = fruit_behind_leaf(false);
  const RayScene scene(w);
  const FruitView v = view_fruit(scene, scene.part_of_instance(1), w.truth.fruits.at(0).surface_points,
                                 Vec3(0.0, 0.25, 0.5));
  EXPECT_GT(v.facing_points, 0);
  EXPECT_EQ(v.hidden_points, 0);
}

TEST(Visibility, CameraPositionsFollowTheProtocolsAngles) {
  const Vec3 target(1.0, 0.75, 0.5), toward(0.0, -1.0, 0.0), along(1.0, 0.0, 0.0);
  const Vec3 front = camera_eye(target, toward, along, {"f", 0.0, 90.0}, 0.5);
  EXPECT_TRUE(front.isApprox(Vec3(1.0, 0.25, 0.5), 1e-12));
  const Vec3 up = camera_eye(target, toward, along, {"u", 0.0, 60.0}, 0.5);  // looking up: below the target
  EXPECT_NEAR(up.z(), 0.5 - 0.5 * std::cos(M_PI / 3.0), 1e-12);
  EXPECT_NEAR(up.y(), 0.75 - 0.5 * std::sin(M_PI / 3.0), 1e-12);
  const Vec3 right = camera_eye(target, toward, along, {"r", 30.0, 90.0}, 0.5);  // looks towards +x: stands at lower x
  EXPECT_LT(right.x(), 1.0);
  EXPECT_NEAR((right - target).norm(), 0.5, 1e-12);
  EXPECT_EQ(hemming_positions().size(), 14u);
}

TEST(Visibility, ProtocolOnAHandBuiltRow) {
  const world::World w = fruit_behind_leaf(true);
  const VisibilityResult r = measure_visibility(w);
  ASSERT_EQ(r.fruits.size(), 1u);
  ASSERT_EQ(r.sections.size(), 1u);
  EXPECT_EQ(r.cameras.size(), 14u);
  // The front level camera sees the fruit half hidden: detectable at the 50 % limit or not,
  // the positions turned towards +x (which look past the leaf's edge) see it whole.
  const auto& pos = r.params.positions;
  for (size_t p = 0; p < pos.size(); ++p)
    if (pos[p].azimuth_deg == -60.0 && pos[p].zenith_deg == 90.0) {
      EXPECT_LT(r.fruits[0].views[p].occlusion(), 0.05);
      EXPECT_TRUE(r.fruits[0].detectable[p]);
    }
  EXPECT_DOUBLE_EQ(r.best.at(0).detectability, 1.0);
}

TEST(Visibility, BestCombinationIsExhaustive) {
  // Three fruits: position 0 sees fruit 0, position 1 fruits 1 and 2, position 2 fruit 0 and 1.
  std::vector<FruitVisibility> f(3);
  f[0].detectable = {true, false, true};
  f[1].detectable = {false, true, true};
  f[2].detectable = {false, true, false};
  const BestCombination one = best_combination(f, 3, 1);
  EXPECT_EQ(one.positions, std::vector<int>({1}));
  EXPECT_NEAR(one.detectability, 2.0 / 3.0, 1e-12);
  const BestCombination two = best_combination(f, 3, 2);
  EXPECT_DOUBLE_EQ(two.detectability, 1.0);
  EXPECT_EQ(two.positions, std::vector<int>({0, 1}));
}

}  // namespace
}  // namespace canopy::evaluation

namespace canopy::evaluation {
namespace {

// The dense preset's occlusion matches the commercial crop's under the protocol (Hemming et
// al.: best single position at most 69 %, best five about 90 %) on the seeds it was calibrated
// on (1-3; the experiments use 1001-1010).
VisibilityResult measure_file(const std::string& path, std::uint64_t seed, int points_per_fruit = 300) {
  world::WorldSpec spec = world::WorldSpec::load(path);
  spec.seed = seed;
  VisibilityParams params;
  params.points_per_fruit = points_per_fruit;
  return measure_visibility(world::generate_world(spec), params);
}

TEST(Visibility, DensePresetMatchesTheCommercialCrop) {
  for (std::uint64_t seed : {1, 2, 3}) {
    // 100 surface points per fruit keep it fast; docs/visibility.md's figures use 300.
    const VisibilityResult r = measure_file("worlds/dense.yaml", seed, 100);
    ASSERT_GT(r.fruits.size(), 20u);
    std::printf("dense seed %d: %zu fruits, best k=1..5: %.3f %.3f %.3f %.3f %.3f\n", int(seed), r.fruits.size(),
                r.best[0].detectability, r.best[1].detectability, r.best[2].detectability, r.best[3].detectability,
                r.best[4].detectability);
    EXPECT_LE(r.best[0].detectability, 0.69) << "seed " << seed;
    EXPECT_GE(r.best[4].detectability, 0.85) << "seed " << seed;
    EXPECT_LE(r.best[4].detectability, 0.95) << "seed " << seed;
  }
}

TEST(Visibility, SameWorldSameResult) {
  const VisibilityResult a = measure_file("worlds/small.yaml", 3), b = measure_file("worlds/small.yaml", 3);
  ASSERT_EQ(a.fruits.size(), b.fruits.size());
  for (size_t i = 0; i < a.fruits.size(); ++i)
    for (size_t p = 0; p < a.fruits[i].views.size(); ++p) {
      EXPECT_EQ(a.fruits[i].views[p].facing_points, b.fruits[i].views[p].facing_points);
      EXPECT_EQ(a.fruits[i].views[p].hidden_points, b.fruits[i].views[p].hidden_points);
    }
}

}  // namespace
}  // namespace canopy::evaluation
