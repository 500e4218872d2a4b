// The world file's keys come from WorldSpec::visit (world_spec.h): YAML out reads back to the
// same spec, world.json's `spec` loads back to the same spec, the defaults file restates the
// struct's defaults, the limits hold on every key, and docs/plants.md's table is current.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/common/params.h"
#include "canopy/world/world_spec.h"

namespace canopy::world {
namespace {

std::string spec_file(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A spec with a non-default value in every section.
WorldSpec changed_spec() {
  WorldSpec s;
  s.name = "changed.1";
  s.seed = 42;
  s.classes.names = {"background", "leaf", "stem", "fruit"};
  s.part_classes.stem = "stem";
  s.rows.rows = 1;
  s.rows.plants_per_row = 3;
  s.rows.x_start_m = -0.25;
  s.plant.height_min_m = 0.9;
  s.plant.leaves_per_stem_max = 11;
  s.plant.leaves_per_stem_min = 7;
  s.plant.fruit_colors = {{"orange", 0.25}, {"green", 0.75}};
  s.plant.ripe_colors = {"orange"};
  s.camera.width_px = 320;
  s.camera.cx_px = 160.0;
  s.camera.depth_noise_k = 0.01;
  s.robot_start = BasePose{-1.5, 0.1, 0.2};
  s.gt_point_spacing_m = 0.004;
  return s;
}

TEST(WorldSpec, YamlOutReadsBackToTheSameSpec) {
  for (const WorldSpec& s : {WorldSpec{}, changed_spec()}) {
    const std::string text = yaml_text(params_to_yaml(s));
    const WorldSpec back = WorldSpec::load(spec_file("round_trip.yaml", text));
    EXPECT_TRUE(same_params(s, back)) << text;
    EXPECT_EQ(back.to_json(), s.to_json());
    EXPECT_EQ(back.camera.cx_px, s.camera.cx_px);
    EXPECT_EQ(back.plant.fruit_colors, s.plant.fruit_colors);
  }
}

TEST(WorldSpec, SavedJsonLoadsBackForEveryWorld) {
  for (const char* file : {"worlds/default.yaml", "worlds/small.yaml", "worlds/ablation.yaml"}) {
    const WorldSpec s = WorldSpec::load(find_data_file(file));
    const nlohmann::json j = s.to_json();
    // world.json's spec: every key of the file, `plants` beside them.
    for (const char* key : {"name", "seed", "classes", "target_class", "part_classes", "rows", "plant", "camera",
                            "robot_start", "gt_point_spacing_m", "plants"})
      EXPECT_TRUE(j.contains(key)) << file << " " << key;
    EXPECT_TRUE(j["rows"]["plants_per_row"].is_number_integer());
    EXPECT_TRUE(j["plant"]["height_m"][0].is_number_float());
    EXPECT_TRUE(j["camera"]["width_px"].is_number_integer());
    const WorldSpec back = WorldSpec::load(spec_file("saved.yaml", j.dump(2)));  // JSON is YAML
    EXPECT_TRUE(same_params(s, back)) << file;
    EXPECT_EQ(back.to_json(), j) << file;
  }
}

TEST(WorldSpec, DefaultsFileEqualsStructDefaults) {
  WorldSpec file = WorldSpec::load(find_data_file("worlds/default.yaml"));
  EXPECT_TRUE(file.placements.empty());
  // The one key the file sets apart: the robot starts before the first plant, while a spec
  // built in code starts at the origin (tests place the robot themselves).
  EXPECT_EQ(file.robot_start.x_m, -0.8);
  EXPECT_EQ(WorldSpec{}.robot_start.x_m, 0.0);
  file.robot_start = WorldSpec{}.robot_start;
  EXPECT_TRUE(same_params(file, WorldSpec{})) << yaml_text(params_to_yaml(file));
}

TEST(WorldSpec, CameraCentredUnlessGiven) {
  const WorldSpec s = WorldSpec::load(spec_file("wide.yaml", "camera: {width_px: 640, height_px: 480}\n"));
  EXPECT_EQ(s.camera.cx_px, 320.0);
  EXPECT_EQ(s.camera.cy_px, 240.0);
}

// The bad-input limits of docs/commands.md, each named with its key and value.
TEST(WorldSpec, LimitsNameKeyAndValue) {
  const std::pair<const char*, const char*> cases[] = {
      {"plant: {leaves_per_stem: [10, 201]}\n", "key 'plant.leaves_per_stem': value '[10, 201]' must be [min, max] of whole numbers, each in [0, 200]"},
      {"plant: {fruits: [3, 51]}\n", "key 'plant.fruits': value '[3, 51]' must be [min, max] of whole numbers, each in [0, 50]"},
      {"plant: {fruits: [5, 3]}\n", "key 'plant.fruits': value '[5, 3]' must have min <= max"},
      {"plant: {height_m: [1.0, 10.5]}\n", "key 'plant.height_m': value '[1.0, 10.5]' must be [min, max] of numbers, each in (0, 10]"},
      {"plant: {leaf_width_ratio: 200}\n", "key 'plant.leaf_width_ratio': value '200' makes blades wider than a plant"},
      {"plant: {ripe_colors: [purple]}\n", "key 'plant.ripe_colors': value '[purple]' holds an unknown colour"},
      {"plant: {fruit_colors: {red: -1}}\n", "key 'plant.fruit_colors': value '{red: -1}' must map colours"},
      {"plant: {fruit_colors: {red: 0}}\n", "key 'plant.fruit_colors': value '{red: 0}' must not have all weights zero"},
      {"rows: {x_start_m: 1001}\n", "key 'rows.x_start_m': value '1001' must be in [-1000, 1000]"},
      {"rows: {plant_spacing_m: 400}\n", "key 'rows.plant_spacing_m': value '400' makes a row longer than the world"},
      {"rows: {row_offset_m: 0.2}\n", "key 'rows.row_offset_m': value '0.2' must be in [0.25, 1000]"},
      {"rows: {rows: 3}\n", "key 'rows.rows': value '3' must be in [1, 2]"},
      {"robot_start: [1001, 0, 0]\n", "key 'robot_start': value '[1001, 0, 0]' lies outside the world"},
      {"robot_start: [0, 0]\n", "key 'robot_start': value '[0, 0]' must be [x, y, yaw] of numbers"},
      {"name: ''\n", "key 'name': value '' must be 1-64 letters"},
      {"name: a/b\n", "key 'name': value 'a/b' must be 1-64 letters"},
      {"seed: -1\n", "key 'seed': value '-1' must be >= 0"},
      {"gt_point_spacing_m: 0.0001\n", "key 'gt_point_spacing_m': value '0.0001' must be >= 0.0005"},
      {"camera: {width_px: 4097, cx_px: 2048}\n", "key 'camera.width_px': value '4097' must be in [1, 4096]"},
      {"camera: {fx_px: 400}\n", "key 'camera.fy_px': value '381.36' must equal fx_px"},
  };
  for (const auto& [yaml, fragment] : cases) {
    const std::string path = spec_file("limits.yaml", yaml);
    try {
      WorldSpec::load(path);
      ADD_FAILURE() << "no error for: " << yaml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": " + fragment), std::string::npos) << e.what();
    }
  }
  // A name of 64 characters is fine, 65 is not.
  EXPECT_NO_THROW(WorldSpec::load(spec_file("long.yaml", "name: " + std::string(64, 'a') + "\n")));
  EXPECT_THROW(WorldSpec::load(spec_file("long.yaml", "name: " + std::string(65, 'a') + "\n")), InputError);
}

TEST(WorldSpec, LimitsHoldForSpecsBuiltInCode) {
  WorldSpec s;
  s.plant.leaves_per_stem_max = kMaxLeavesPerStem + 1;
  EXPECT_THROW(s.validate(), InputError);
  s = WorldSpec{};
  s.rows.x_start_m = 2 * kMaxWorldExtentM;
  EXPECT_THROW(s.validate(), InputError);
  s = WorldSpec{};
  s.camera.fx_px = -1.0;
  EXPECT_THROW(s.validate(), InputError);
  EXPECT_NO_THROW(WorldSpec{}.validate());
}

// docs/plants.md holds what `canopy settings --world --markdown` prints.
TEST(WorldSpec, DocsTableIsCurrent) {
  const std::string doc = read_file(find_data_file("docs/plants.md"));
  const std::string begin = "<!-- generated by: canopy settings --world --markdown -->\n";
  const std::string end = "<!-- end of generated table -->";
  const std::size_t a = doc.find(begin), b = doc.find(end);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_EQ(doc.substr(a + begin.size(), b - a - begin.size()), params_markdown(describe_params(WorldSpec{})))
      << "regenerate docs/plants.md's table with 'canopy settings --world --markdown'";
}

// The sun: fixed unless the world file asks for one per seed; then drawn from the seed alone,
// inside the file's ranges, and different across seeds.
TEST(WorldSpec, SunIsFixedByDefaultAndDrawnPerSeedWhenAsked) {
  Lighting fixed;
  Vec3 dir;
  double diffuse = 0.0;
  fixed.sun(7, &dir, &diffuse);
  EXPECT_TRUE(dir.isApprox(Vec3(-0.3, 0.2, -1.0)));
  EXPECT_DOUBLE_EQ(diffuse, 0.55);
  Lighting drawn;
  drawn.per_seed = true;
  Vec3 a, b, a2;
  double da = 0.0, db = 0.0, da2 = 0.0;
  drawn.sun(1, &a, &da);
  drawn.sun(2, &b, &db);
  drawn.sun(1, &a2, &da2);
  EXPECT_EQ(a, a2);
  EXPECT_EQ(da, da2);
  EXPECT_FALSE(a.isApprox(b));
  for (const Vec3& d : {a, b}) {
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    const double elevation = std::asin(-d.z()) * 180.0 / M_PI;
    EXPECT_GE(elevation, drawn.elevation_min_deg - 1e-9);
    EXPECT_LE(elevation, drawn.elevation_max_deg + 1e-9);
  }
  EXPECT_GE(da, drawn.diffuse_min);
  EXPECT_LE(da, drawn.diffuse_max);
}

}  // namespace
}  // namespace canopy::world
