// The world job against worlds the test writes itself: an imported plant whose ripe fruit is
// red passes the colour check, one whose ripe fruit is leaf green is refused under colour
// labels (naming the plant and the material) and passes under true labels; the seed and the
// aisle check of the world file.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <set>

#include "canopy/common/error.h"
#include "canopy/evaluation/segmentation_check.h"
#include "canopy/jobs/world_job.h"
#include "canopy/world/plant_import.h"
#include "plant_files.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;

// A one-plant world of the test plant (plant_files.h), its ripe fruit material coloured `rgb`.
std::string plant_world(const std::string& name, const std::string& rgb) {
  const std::string dir = testing::TempDir() + "/world_job_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string dae = test_plant::collada(true);
  const std::string effect = "<effect id=\"e_Capsicum_frt1\"><profile_COMMON><technique sid=\"common\"><lambert><diffuse><color>";
  const std::size_t at = dae.find(effect) + effect.size();
  dae.replace(at, dae.find(" 1</color>", at) - at, rgb);
  test_plant::write_text(dir + "/plant.dae", dae);
  world::ImportOptions o;
  o.rules = world::class_preset("capsicum");
  world::import_plant(dir + "/plant.dae", o).save(dir + "/plant");
  test_plant::write_text(dir + "/world.yaml", "name: " + name + "\nseed: 3\nrows: {rows: 1, plants_per_row: 1, "
                                              "position_jitter_m: 0.0}\nplants:\n  - {plant: {import: " + dir +
                                              "/plant}, slot: [0, 0]}\n");
  return dir + "/world.yaml";
}

WorldJobParams params(const std::string& file, perception::LabelSource source) {
  WorldJobParams p;
  p.world_file = file;
  p.extractor.source = source;
  return p;
}

TEST(WorldJob, RedFruitPassesTheColourCheck) {
  const world::World w = load_world(params(plant_world("red", "0.8 0.1 0.05"), perception::LabelSource::kColor));
  EXPECT_EQ(w.plants.size(), 1u);
  EXPECT_EQ(w.truth.fruits.size(), 2u);
}

TEST(WorldJob, GreenRipeFruitIsRefusedUnderColourLabelsOnly) {
  const std::string file = plant_world("green", "0.2 0.6 0.1");
  try {
    load_world(params(file, perception::LabelSource::kColor));
    FAIL() << "a ripe fruit colour segmentation cannot see was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("/plant: material 'Capsicum_frt1'"), std::string::npos) << m;
    EXPECT_NE(m.find("(labels: color;"), std::string::npos) << m;
  }
  const world::World w = load_world(params(file, perception::LabelSource::kTruth));
  EXPECT_EQ(w.plants.size(), 1u);
  // The check alone gives the same verdicts on the built world.
  EXPECT_THROW(check_world_colours(w, params(file, perception::LabelSource::kColor).extractor), InputError);
  EXPECT_NO_THROW(check_world_colours(w, params(file, perception::LabelSource::kTruth).extractor));
}

TEST(WorldJob, SeedReplacesTheFilesAndTheWorldIsTheGeneratorsWorld) {
  WorldJobParams p = params("worlds/small.yaml", perception::LabelSource::kColor);
  p.seed = 77;
  const world::World w = load_world(p);
  EXPECT_EQ(w.spec.seed, 77u);
  world::WorldSpec spec = world::WorldSpec::load("worlds/small.yaml");
  spec.seed = 77;
  const world::World direct = world::generate_world(spec);
  ASSERT_EQ(w.truth.fruits.size(), direct.truth.fruits.size());
  for (std::size_t i = 0; i < w.truth.fruits.size(); ++i)
    EXPECT_EQ(w.truth.fruits[i].center, direct.truth.fruits[i].center);
  EXPECT_EQ(w.triangle_count(), direct.triangle_count());
  const YAML::Node run = run_record("map", w.spec);
  EXPECT_EQ(run["command"].as<std::string>(), "map");
  EXPECT_EQ(run["world"]["seed"].as<std::uint64_t>(), 77u);
}

TEST(WorldJob, AnAisleNarrowerThanTheBaseIsRefused) {
  const std::string dir = testing::TempDir() + "/world_job_aisle";
  fs::create_directories(dir);
  std::ofstream(dir + "/narrow.yaml") << "name: narrow\nrows: {row_offset_m: 0.3}\n";
  try {
    load_world_spec(dir + "/narrow.yaml");
    FAIL() << "rows at +-0.3 m accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("narrow.yaml: key 'rows.row_offset_m'"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(load_world_spec("worlds/small.yaml"));
}

// The base's prismatic joints end at +-250 m (the URDF): a row past them, or a start outside
// them, is refused naming the key; a row that ends just inside them is accepted.
TEST(WorldJob, RowsAndStartsBeyondTheBasesJointsAreRefused) {
  const std::string dir = testing::TempDir() + "/world_job_range";
  fs::create_directories(dir);
  const RobotConfig robot = default_robot_config();
  const world::WorldSpec::BaseRange r = base_range(robot, robot::RobotDescription::load_urdf(robot.urdf_path));
  EXPECT_EQ(r.x_lower_m, -250.0);
  EXPECT_EQ(r.x_upper_m, 250.0);
  const auto refused = [&](const std::string& name, const std::string& text, const std::string& key) {
    std::ofstream(dir + "/" + name) << text;
    try {
      load_world_spec(dir + "/" + name);
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name + ": key '" + key + "'"), std::string::npos) << e.what();
    }
  };
  // Four plants from x = 249 m; the last one needs the base past 250 m.
  refused("far_row.yaml", "name: far\nrows: {rows: 2, plants_per_row: 4, plant_spacing_m: 0.5, x_start_m: 249}\n"
          "robot_start: [248.5, 0, 0]\n", "rows.x_start_m");
  refused("far_start.yaml", "name: far\nrows: {rows: 2, plants_per_row: 1}\nrobot_start: [300, 0, 0]\n", "robot_start");
  refused("low_row.yaml", "name: far\nrows: {rows: 2, plants_per_row: 2, x_start_m: -400}\nrobot_start: [0, 0, 0]\n",
          "rows.x_start_m");
  // The last plant with the arm over it and the base just inside the joint: accepted.
  const double last_ok = 250.0 + r.arm_x_m;
  std::ofstream(dir + "/edge.yaml") << "name: edge\nrows: {rows: 2, plants_per_row: 2, plant_spacing_m: 0.5, x_start_m: "
                                    << last_ok - 0.5 << "}\nrobot_start: [" << last_ok - 1.5 << ", 0, 0]\n";
  EXPECT_NO_THROW(load_world_spec(dir + "/edge.yaml"));
  // The greenhouse compartment (issue 49): two rows of 500 dense plants, 150 m, within reach;
  // beyond the joints' old +-100 m it would be refused.
  const world::WorldSpec house = load_world_spec("worlds/greenhouse.yaml");
  EXPECT_EQ(house.plant_count(), 1000);
  world::WorldSpec::BaseRange old_range = r;
  old_range.x_lower_m = -100.0;
  old_range.x_upper_m = 100.0;
  EXPECT_THROW(house.check_base_range(old_range), InputError);
}

// Every material of the default world (ground, procedural plants) is labelled as its class;
// a floor of fruit colour is false fruit: a warning, an error under --strict (strict_colours).
TEST(WorldJob, EveryMaterialIsCheckedAndAFruitColouredFloorIsCaught) {
  WorldJobParams p = params("worlds/default.yaml", perception::LabelSource::kColor);
  p.strict_colours = true;
  const world::World w = load_world(p);  // no throw: nothing of the default world is mislabelled
  const auto checked = evaluation::check_color_segmentation(w, p.extractor.color);
  std::set<std::string> names;
  for (const auto& m : checked) {
    EXPECT_TRUE(m.problem.empty()) << m.owner << " " << m.material << ": " << m.problem;
    names.insert(m.owner + "/" + m.material);
  }
  for (const char* n : {"ground/film", "ground/path", "procedural plants/leaf", "procedural plants/stem",
                        "procedural plants/fruit (red)", "procedural plants/fruit (yellow)"})
    EXPECT_EQ(names.count(n), 1u) << n;

  const std::string dir = testing::TempDir() + "/world_job_floor";
  fs::create_directories(dir);
  std::ofstream(dir + "/red_floor.yaml") << "name: red_floor\nseed: 3\nrows: {rows: 1, plants_per_row: 1}\n"
                                            "ground: {film_rgb: [0.42, 0.36, 0.30]}\n";
  WorldJobParams red = params(dir + "/red_floor.yaml", perception::LabelSource::kColor);
  const world::World rw = load_world(red);  // a warning only
  bool flagged = false;
  for (const auto& m : evaluation::check_color_segmentation(rw, red.extractor.color))
    if (m.owner == "ground" && m.material == "film") {
      flagged = true;
      EXPECT_NE(m.problem.find("false fruit"), std::string::npos) << m.problem;
    }
  EXPECT_TRUE(flagged);
  red.strict_colours = true;
  try {
    load_world(red);
    FAIL() << "a fruit-coloured floor passed under strict_colours";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground: material 'film'"), std::string::npos) << e.what();
  }
  // Under true labels the floor's colour does not matter.
  red.extractor.source = perception::LabelSource::kTruth;
  red.strict_colours = false;
  EXPECT_NO_THROW(load_world(red));
}


// The dense preset's heating pipes are checked like the floor, and never lie in the aisle.
TEST(WorldJob, HeatingPipesAreCheckedAndKeptOutOfTheAisle) {
  WorldJobParams p = params("worlds/dense.yaml", perception::LabelSource::kColor);
  p.strict_colours = true;
  const world::World w = load_world(p);
  ASSERT_TRUE(w.spec.ground.heating_pipes);
  bool checked = false;
  for (const auto& m : evaluation::check_color_segmentation(w, p.extractor.color))
    if (m.owner == "ground" && m.material == "heating pipes") {
      checked = true;
      EXPECT_TRUE(m.problem.empty()) << m.problem;
    }
  EXPECT_TRUE(checked);

  const std::string dir = testing::TempDir() + "/world_job_pipes";
  fs::create_directories(dir);
  std::ofstream(dir + "/red_pipes.yaml") << "name: red_pipes\nseed: 3\nrows: {rows: 1, plants_per_row: 1}\n"
                                            "ground: {heating_pipes: true, pipe_rgb: [0.7, 0.1, 0.05]}\n";
  WorldJobParams red = params(dir + "/red_pipes.yaml", perception::LabelSource::kColor);
  red.strict_colours = true;
  try {
    load_world(red);
    FAIL() << "red heating pipes passed under strict_colours";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground: material 'heating pipes'"), std::string::npos) << e.what();
  }
  std::ofstream(dir + "/aisle_pipes.yaml") << "name: aisle_pipes\nseed: 3\nrows: {rows: 1, plants_per_row: 1}\n"
                                             "ground: {heating_pipes: true, pipe_offset_m: 0.6}\n";
  try {
    load_world_spec(dir + "/aisle_pipes.yaml");
    FAIL() << "heating pipes in the aisle accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("aisle_pipes.yaml: key 'ground.pipe_offset_m': value '0.6'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace canopy::jobs
