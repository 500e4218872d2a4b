#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/world/world.h"
#include "same_plants.h"

namespace canopy::world {
namespace {

WorldSpec small_spec(std::uint64_t seed) {
  WorldSpec s;
  s.seed = seed;
  s.rows.rows = 1;
  s.rows.plants_per_row = 2;
  return s;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(WorldGeneration, SameSeedSameWorldOtherSeedOtherWorld) {
  const World a = generate_world(small_spec(7));
  const World b = generate_world(small_spec(7));
  const World c = generate_world(small_spec(8));
  ASSERT_EQ(a.plants.size(), b.plants.size());
  for (size_t p = 0; p < a.plants.size(); ++p) {
    ASSERT_EQ(a.plants[p].parts.size(), b.plants[p].parts.size());
    for (size_t k = 0; k < a.plants[p].parts.size(); ++k)
      EXPECT_EQ(a.plants[p].parts[k].mesh.vertices, b.plants[p].parts[k].mesh.vertices);
  }
  ASSERT_EQ(a.truth.fruits.size(), b.truth.fruits.size());
  for (size_t f = 0; f < a.truth.fruits.size(); ++f)
    EXPECT_EQ(a.truth.fruits[f].surface_points, b.truth.fruits[f].surface_points);
  bool differs = a.plants.size() != c.plants.size();
  for (size_t p = 0; !differs && p < a.plants.size(); ++p)
    differs = a.plants[p].parts.size() != c.plants[p].parts.size() ||
              a.plants[p].parts[0].mesh.vertices != c.plants[p].parts[0].mesh.vertices;
  EXPECT_TRUE(differs);
}

// Trellis strings are extra parts: two per plant (one per stem), of their own class, and every
// other part of the world is the same as without them (they draw no random numbers).
TEST(WorldGeneration, TrellisStringsAddTwoPartsPerPlantAndChangeNothingElse) {
  WorldSpec with = small_spec(5);
  with.plant.trellis_strings = true;
  const World a = generate_world(small_spec(5)), b = generate_world(with);
  ASSERT_EQ(a.plants.size(), b.plants.size());
  for (size_t i = 0; i < a.plants.size(); ++i) {
    const auto& pa = a.plants[i].parts;
    const auto& pb = b.plants[i].parts;
    ASSERT_EQ(pb.size(), pa.size() + 2);
    for (size_t k = 0; k < pa.size(); ++k) {
      EXPECT_EQ(pa[k].name, pb[k].name);
      EXPECT_EQ(pa[k].mesh.vertices, pb[k].mesh.vertices);
    }
    for (size_t k = pa.size(); k < pb.size(); ++k) {
      EXPECT_EQ(pb[k].kind, "trellis");
      EXPECT_EQ(pb[k].class_id, with.classes.index_of("background"));
      Vec3 lo, hi;
      pb[k].mesh.bounds(&lo, &hi);
      EXPECT_GT(hi.z(), a.plants[i].height_m);  // up to the wire above the plant
    }
  }
  EXPECT_EQ(a.truth.total_points(), b.truth.total_points());
}

TEST(WorldGeneration, DefaultWorldHasEightDistinctPlantsWithLabelledParts) {
  const WorldSpec spec = WorldSpec::load(find_data_file("worlds/default.yaml"));
  const World w = generate_world(spec);
  ASSERT_EQ(w.plants.size(), 8u);
  std::set<std::pair<long, size_t>> signatures;  // (height in mm, part count)
  int next_instance = 0;
  for (const auto& p : w.plants) {
    signatures.insert({std::lround(p.height_m * 1000), p.parts.size()});
    EXPECT_GE(p.height_m, spec.plant.height_min_m);
    EXPECT_LE(p.height_m, spec.plant.height_max_m);
    int fruits = 0;
    for (const auto& part : p.parts) {
      EXPECT_GT(part.mesh.volume(), 0.0) << part.name;  // closed, outward meshes
      EXPECT_EQ(part.class_id, spec.class_of(part.kind)) << part.name;
      if (part.kind == "fruit") {
        EXPECT_EQ(part.instance_id, next_instance++);
        ++fruits;
      } else {
        EXPECT_EQ(part.instance_id, kNoInstance);
      }
    }
    EXPECT_GE(fruits, spec.plant.fruits_min);
    EXPECT_LE(fruits, spec.plant.fruits_max);
    // Plants face the aisle: rows on both sides of y = 0.
    EXPECT_NEAR(std::abs(p.base_position.y()), spec.rows.row_offset_m, spec.rows.position_jitter_m + 1e-9);
  }
  EXPECT_EQ(signatures.size(), 8u) << "plants should differ from each other";
}

// Each plant draws from its own seed (issue 49): generated alone from its slot's base and
// first instance id, it is the whole world's plant bit for bit, on both rows and across seeds.
TEST(WorldGeneration, APlantGeneratedAloneIsTheWholeWorldsBitForBit) {
  for (const std::uint64_t seed : {1u, 42u}) {
    WorldSpec spec;  // two rows of four
    spec.seed = seed;
    spec.plant.trellis_strings = seed == 42u;
    const World w = generate_world(spec);
    ASSERT_EQ(w.plants.size(), 8u);
    int next_instance = 0;
    for (const Plant& p : w.plants) {
      EXPECT_TRUE(p.held);
      EXPECT_EQ(p.first_instance, next_instance);
      int fruits = 0;
      std::size_t triangles = 0;
      for (const PlantPart& part : p.parts) {
        fruits += part.instance_id != kNoInstance;
        triangles += part.mesh.faces.size();
      }
      EXPECT_EQ(p.triangles, triangles);
      next_instance += fruits;
      canopy::test::expect_same_plant(generate_plant(spec, p.index, p.base_position, p.first_instance), p);
      // The world's own plant, not a copy, when it is held.
      EXPECT_EQ(w.plant(static_cast<std::size_t>(p.index)).get(), &p);
    }
  }
}

// A world generated with its plants dropped once they hold N triangles is the same world: the
// same ground truth, counts and notes, and every plant World::plant() makes again is the held
// world's, bit for bit. Below the threshold every plant is held.
TEST(WorldGeneration, AWorldThatDropsItsPlantsIsTheSameWorld) {
  WorldSpec spec;
  spec.rows.plants_per_row = 5;
  spec.plant.fruits_min = 14;  // crowded: some drawn fruits do not fit (the notes)
  spec.plant.fruits_max = 24;
  const World held = generate_world(spec);
  ASSERT_TRUE(held.plants_held());
  const double first_three = static_cast<double>(held.plants[0].triangles + held.plants[1].triangles + held.plants[2].triangles);
  for (const double from : {0.0, first_three, static_cast<double>(held.triangle_count())}) {
    GenerateOptions options;
    options.drop_plants_from_triangles = from;
    const World w = generate_world(spec, options);
    ASSERT_EQ(w.plants.size(), held.plants.size());
    for (std::size_t i = 0; i < w.plants.size(); ++i) {
      const Plant& p = w.plants[i];
      EXPECT_FALSE(p.held) << i;  // the plants before the threshold are dropped too
      EXPECT_TRUE(p.parts.empty()) << i;
      EXPECT_EQ(p.base_position, held.plants[i].base_position);
      EXPECT_EQ(p.height_m, held.plants[i].height_m);
      canopy::test::expect_same_plant(*w.plant(i), held.plants[i]);
    }
    EXPECT_FALSE(w.plants_held());
    EXPECT_EQ(w.triangle_count(), held.triangle_count());
    EXPECT_EQ(unplaced_fruit_notes(w), unplaced_fruit_notes(held));
    canopy::test::expect_same_truth(w.truth, held.truth);
    canopy::test::expect_same_truth(sample_ground_truth(w), held.truth);
  }
  EXPECT_FALSE(unplaced_fruit_notes(held).empty()) << "the test means a crowded world";
  GenerateOptions above;
  above.drop_plants_from_triangles = static_cast<double>(held.triangle_count()) + 1.0;
  const World all = generate_world(spec, above);
  EXPECT_TRUE(all.plants_held());
  for (std::size_t i = 0; i < all.plants.size(); ++i) canopy::test::expect_same_plant(all.plants[i], held.plants[i]);
}

// Targets are the ripe colours (issue 10 point 2): green fruit is generated, rendered and
// labelled with part_classes.unripe_fruit, but is no target; ripe_colors is configurable.
TEST(GroundTruth, TargetFlagsFollowTheRipeColours) {
  WorldSpec spec;  // default: 8 plants, 10 % green fruit
  const World w = generate_world(spec);
  std::size_t green = 0, targets = 0;
  for (const FruitTruth& f : w.truth.fruits) {
    EXPECT_EQ(f.target, f.color != "green") << f.instance_id << " " << f.color;
    green += f.color == "green";
    targets += f.target;
  }
  ASSERT_GT(green, 0u) << "the default world should hold unripe fruit";
  EXPECT_EQ(w.truth.target_count(), targets);
  for (const Plant& p : w.plants)
    for (const PlantPart& part : p.parts)
      if (part.instance_id != kNoInstance) {
        EXPECT_EQ(part.fruit_target, part.fruit_color != "green");
        EXPECT_EQ(part.class_id, spec.classes.index_of("fruit"));  // both map to fruit by default
      }
  // Only red counts; unripe fruit labelled leaf.
  const std::string path = write_temp("ripe_world.yaml",
                                      "plant: {ripe_colors: [red]}\npart_classes: {unripe_fruit: leaf}\n");
  const WorldSpec only_red = WorldSpec::load(path);
  const World w2 = generate_world(only_red);
  for (const Plant& p : w2.plants)
    for (const PlantPart& part : p.parts) {
      if (part.instance_id == kNoInstance) continue;
      EXPECT_EQ(part.class_id, only_red.classes.index_of(part.fruit_color == "red" ? "fruit" : "leaf"));
    }
  for (const FruitTruth& f : w2.truth.fruits) EXPECT_EQ(f.target, f.color == "red");
  {
    const std::string bad = write_temp("ripe_bad.yaml", "plant: {ripe_colors: [purple]}\n");
    EXPECT_THROW(WorldSpec::load(bad), InputError);
  }
}

// The defaults file against the struct's defaults: world_spec_test.cpp.

void expect_error(const std::string& yaml, const std::string& fragment) {
  const std::string path = write_temp("bad_world.yaml", yaml);
  try {
    WorldSpec::load(path);
    FAIL() << "no error for: " << yaml;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
  }
}

TEST(WorldSpec, BadInputNamesFileKeyAndValue) {
  expect_error("seed: 1\nrows: {plantz_per_row: 3}\n", "unknown key 'rows.plantz_per_row'");
  expect_error("plant: {height_m: [-1.0, 1.0]}\n", "key 'plant.height_m': value '[-1.0, 1.0]'");
  expect_error("camera: {fx_px: 0}\n", "camera.fx_px");
  expect_error("rows: {plants_per_row: many}\n", "key 'rows.plants_per_row': value 'many'");
  expect_error("seed: [1, 2\n", "malformed YAML");
  expect_error("target_class: flower\n", "target_class");
  EXPECT_THROW(WorldSpec::load("/nonexistent/world.yaml"), InputError);
}

TEST(WorldSpec, ImplausibleSizesAreRejected) {
  // Sizes this large once overflowed the scene writer's number buffers.
  expect_error("plant: {height_m: [1.0e30, 1.0e30]}\n", "key 'plant.height_m'");
  expect_error("plant: {leaf_length_m: [0.1, 1.0e20]}\n", "key 'plant.leaf_length_m'");
  expect_error("rows: {x_start_m: 1.0e15}\n", "key 'rows.x_start_m'");
  expect_error("rows: {plant_spacing_m: 1.0e12}\n", "key 'rows.plant_spacing_m'");
}

TEST(WorldSpec, SavedJsonLoadsBackToTheSameSpec) {
  WorldSpec spec = WorldSpec::load(find_data_file("worlds/default.yaml"));
  // Values that do not survive a short decimal form, and non-default choices everywhere.
  spec.seed = 1234567890123ull;
  spec.name = "odd";
  spec.rows.row_offset_m = 0.1 + 0.2 + 0.45;
  spec.rows.plants_per_row = 3;
  spec.plant.height_min_m = 1.0 / 3.0;
  spec.plant.leaves_per_stem_min = 11;
  spec.plant.fruit_colors = {{"orange", 0.25}, {"red", 0.75}};
  spec.camera.fx_px = spec.camera.fy_px = 400.0 / 7.0;
  spec.robot_start = BasePose{-1.0 / 7.0, 0.01, 0.3};
  spec.part_classes.stem = "background";
  const std::string path = write_temp("saved_world.json", spec.to_json().dump(2));
  const WorldSpec back = WorldSpec::load(path);
  EXPECT_EQ(back.to_json(), spec.to_json());
  EXPECT_EQ(back.rows.row_offset_m, spec.rows.row_offset_m);
  EXPECT_EQ(back.seed, spec.seed);
  // Every key of the JSON is a key the loader reads (no unknown keys), so it also holds every
  // parameter the loader knows: the defaults' JSON has the same keys as the shipped file.
  const WorldSpec defaults;
  EXPECT_EQ(defaults.to_json().size(), back.to_json().size());
}

TEST(WorldSpec, AisleMustFitTheBasePlusClearance) {
  const WorldSpec d;
  const double half_width = 0.335, clearance = 0.05;  // the Husky base, robot.yaml
  EXPECT_NO_THROW(d.check_aisle(half_width, clearance));
  WorldSpec narrow = d;
  narrow.rows.row_offset_m = 0.3;  // rows at +-0.3 m: plants inside the base's footprint
  narrow.source_file = "narrow.yaml";
  try {
    narrow.check_aisle(half_width, clearance);
    FAIL() << "rows at +-0.3 m accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("narrow.yaml: key 'rows.row_offset_m': value '0.3'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("aisle_clearance_m"), std::string::npos) << msg;
  }
  // The boundary: exactly the base, the clearance and the plants' reach fits.
  WorldSpec tight = d;
  tight.rows.row_offset_m = half_width + clearance + d.plant_reach_m() + 1e-9;
  EXPECT_NO_THROW(tight.check_aisle(half_width, clearance));
  tight.rows.row_offset_m -= 2e-9;
  EXPECT_THROW(tight.check_aisle(half_width, clearance), InputError);
}

}  // namespace
}  // namespace canopy::world
