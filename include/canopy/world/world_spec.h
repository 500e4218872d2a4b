#pragma once
// A greenhouse world as written in worlds/<name>.yaml: rows of procedurally generated
// sweet-pepper plants along an aisle, the semantic classes, the camera and the robot start.
// Every key, its limits and its meaning are stated once, in the visit() functions below
// (common/params.h): load() reads a world file through them, to_json() writes world.json's
// `spec` from them, and `canopy settings --world --markdown` prints docs/plants.md's table.
// Only `plants` (imported plant folders, resolved on disk) is read and written by hand.

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
#include "canopy/common/params.h"
#include "canopy/common/types.h"

namespace canopy::world {

/// Largest plant dimension a world may ask for (height or part size) [m].
constexpr double kMaxPlantSizeM = 10.0;
/// Largest distance from the origin that rows and the robot start may reach [m].
constexpr double kMaxWorldExtentM = 1000.0;
/// Most leaves per stem and fruits per plant a world file may ask for (a sweet-pepper stem
/// has tens of leaves and a plant a handful of fruits; more is a typo that would hang the
/// generator or exhaust memory).
constexpr int kMaxLeavesPerStem = 200;
constexpr int kMaxFruitsPerPlant = 50;

namespace spec_detail {
/// A [min, max] pair of fields, each within `each`, min <= max.
template <class Archive, typename T>
void range(Archive& a, const char* key, T& lo, T& hi, const Limits& each, const char* help) {
  a.tuple(key, {&lo, &hi}, "[min, max]", each, help);
  a.check(lo <= hi, key, "must have min <= max");
}
/// A size of plant geometry [m]: (0, kMaxPlantSizeM] (1e30 for 1.3 is a typo, not a plant).
inline Limits plant_size() { return limits::above_up_to(0.0, kMaxPlantSizeM); }
/// A fruit colour the generator knows.
bool known_fruit_color(const std::string& name);
/// True when every name in `names` is a known fruit colour.
bool known_fruit_colors(const std::vector<std::string>& names);
/// True when every colour is known and every weight finite and >= 0.
bool valid_color_weights(const std::map<std::string, double>& weights);
/// True when `name` is 1-64 letters, digits, '_', '-' or '.' without "..".
bool valid_world_name(const std::string& name);
}  // namespace spec_detail

/// Plants in rows parallel to the world x axis, on both sides of an aisle along y = 0.
struct RowLayout {
  int rows = 2;                    ///< 1 (left of the aisle, y > 0) or 2 (both sides).
  int plants_per_row = 4;
  double plant_spacing_m = 0.5;    ///< Along the row.
  double row_offset_m = 0.75;      ///< |y| of each row's centre line.
  double x_start_m = 0.0;          ///< x of the first plant of each row.
  double position_jitter_m = 0.03; ///< Uniform jitter of each plant's position.

  /// The keys of a world file's `rows`.
  template <class Archive>
  void visit(Archive& a) {
    a("rows", rows, limits::in(1, 2), "1: one row left of the aisle (y > 0); 2: both sides");
    a("plants_per_row", plants_per_row, limits::in(1, 1000), "Plants in each row");
    a("plant_spacing_m", plant_spacing_m, limits::positive(), "Distance between plants along a row [m]");
    a.check(plant_spacing_m * (plants_per_row - 1) <= kMaxWorldExtentM, "plant_spacing_m",
            "makes a row longer than the world (at most 1000 m)");
    a("row_offset_m", row_offset_m, limits::in(0.25, kMaxWorldExtentM),
      "Distance of each row's centre line from the aisle's (y = 0) [m]; the robot drives between");
    a("x_start_m", x_start_m, limits::in(-kMaxWorldExtentM, kMaxWorldExtentM), "x of each row's first plant [m]");
    a.check(std::abs(x_start_m + plant_spacing_m * (plants_per_row - 1)) <= kMaxWorldExtentM, "x_start_m",
            "puts the row's last plant outside the world (at most 1000 m from the origin)");
    a("position_jitter_m", position_jitter_m, limits::non_negative(), "Uniform jitter of each plant's position [m]");
    a.check(position_jitter_m < 0.5 * plant_spacing_m, "position_jitter_m", "must be < plant_spacing_m / 2");
  }
};

/// Ranges from which every plant draws its own shape (docs/background/plants.md).
struct PlantParams {
  double height_min_m = 1.0, height_max_m = 1.3;
  double stem_diameter_min_m = 0.012, stem_diameter_max_m = 0.016;
  double v_angle_min_deg = 8.0, v_angle_max_deg = 20.0;   ///< Each stem's lean from vertical.
  int leaves_per_stem_min = 14, leaves_per_stem_max = 20;
  double leaf_length_min_m = 0.08, leaf_length_max_m = 0.15;  ///< Blade length.
  double leaf_width_ratio = 0.5;                           ///< Blade width / length.
  double petiole_length_min_m = 0.03, petiole_length_max_m = 0.08;
  int fruits_min = 3, fruits_max = 6;                      ///< Per plant.
  double fruit_zone_min = 0.35, fruit_zone_max = 0.85;     ///< Fraction of plant height.
  double blocky_fraction = 0.7;                            ///< Else conical.
  double blocky_width_min_m = 0.075, blocky_width_max_m = 0.09;
  double blocky_length_min_m = 0.09, blocky_length_max_m = 0.12;
  double conical_width_min_m = 0.05, conical_width_max_m = 0.06;
  double conical_length_min_m = 0.11, conical_length_max_m = 0.16;
  std::map<std::string, double> fruit_colors = {{"red", 0.6}, {"yellow", 0.3}, {"green", 0.1}};
  /// Ripe colours: their fruits are targets (in the metrics); others are rendered and
  /// labelled (part class unripe_fruit) but not counted, as in the paper's ground truth.
  std::vector<std::string> ripe_colors = {"red", "yellow", "orange"};
  /// V-system support: one string per stem, from the fork up along the stem to a wire above
  /// the plant. Off by default (the plants are the same either way: the strings draw no
  /// random numbers).
  bool trellis_strings = false;

  /// The keys of a world file's `plant` (ranges as [min, max]).
  template <class Archive>
  void visit(Archive& a) {
    using spec_detail::range;
    const Limits size = spec_detail::plant_size();
    range(a, "height_m", height_min_m, height_max_m, size, "Plant height [m]");
    range(a, "stem_diameter_m", stem_diameter_min_m, stem_diameter_max_m, size, "Stem diameter [m]");
    range(a, "v_angle_deg", v_angle_min_deg, v_angle_max_deg, limits::finite(), "Each stem's lean from vertical [deg]");
    range(a, "leaves_per_stem", leaves_per_stem_min, leaves_per_stem_max, limits::in(0, kMaxLeavesPerStem),
          "Leaves on each stem");
    range(a, "leaf_length_m", leaf_length_min_m, leaf_length_max_m, size, "Leaf blade length [m]");
    a("leaf_width_ratio", leaf_width_ratio, limits::positive(), "Blade width / length");
    a.check(leaf_width_ratio * leaf_length_max_m <= kMaxPlantSizeM, "leaf_width_ratio",
            "makes blades wider than a plant (at most 10 m)");
    range(a, "petiole_length_m", petiole_length_min_m, petiole_length_max_m, size, "Petiole length [m]");
    range(a, "fruits", fruits_min, fruits_max, limits::in(0, kMaxFruitsPerPlant), "Fruits per plant");
    range(a, "fruit_zone", fruit_zone_min, fruit_zone_max, limits::above_up_to(0.0, 1.0),
          "Where fruits hang, as fractions of the plant height");
    a("blocky_fraction", blocky_fraction, limits::in(0.0, 1.0), "Share of blocky fruits (the rest conical)");
    range(a, "blocky_width_m", blocky_width_min_m, blocky_width_max_m, size, "Blocky fruit width [m]");
    range(a, "blocky_length_m", blocky_length_min_m, blocky_length_max_m, size, "Blocky fruit length [m]");
    range(a, "conical_width_m", conical_width_min_m, conical_width_max_m, size, "Conical fruit width [m]");
    range(a, "conical_length_m", conical_length_min_m, conical_length_max_m, size, "Conical fruit length [m]");
    a("fruit_colors", fruit_colors, "Weight of each fruit colour (red, yellow, orange, green), each >= 0");
    a.check(spec_detail::valid_color_weights(fruit_colors), "fruit_colors",
            "must map colours (red, yellow, orange, green) to weights >= 0");
    double total = 0.0;
    for (const auto& kv : fruit_colors) total += kv.second;
    a.check(fruits_max == 0 || total > 0.0, "fruit_colors", "must not have all weights zero");
    a("ripe_colors", ripe_colors, "Colours whose fruits are targets (the metrics count them)");
    a.check(spec_detail::known_fruit_colors(ripe_colors), "ripe_colors",
            "holds an unknown colour (use red, yellow, orange, green)");
    a("trellis_strings", trellis_strings,
      "One trellis string per stem, from the fork along the stem to a wire 0.3 m above the plant (V-system)");
  }
};

/// Which semantic class each kind of geometry carries (names from SemanticClasses).
struct PartClasses {
  std::string ground = "background";
  std::string robot = "background";
  std::string stem = "leaf";
  std::string petiole = "leaf";
  std::string leaf = "leaf";
  std::string peduncle = "leaf";
  std::string fruit = "fruit";
  std::string unripe_fruit = "fruit";  ///< Fruits whose colour is not ripe.
  std::string trellis = "background";  ///< Trellis strings (plant.trellis_strings).

  /// The keys of a world file's `part_classes`.
  template <class Archive>
  void visit(Archive& a) {
    a("ground", ground, "Class of the ground");
    a("robot", robot, "Class of the robot's own body");
    a("stem", stem, "Class of stems");
    a("petiole", petiole, "Class of petioles");
    a("leaf", leaf, "Class of leaf blades");
    a("peduncle", peduncle, "Class of peduncles");
    a("fruit", fruit, "Class of ripe fruits");
    a("unripe_fruit", unripe_fruit, "Class of fruits whose colour is not ripe");
    a("trellis", trellis, "Class of trellis strings (plant.trellis_strings)");
  }
};

/// What the floor looks like to the camera: white ground film between and under the rows, as
/// greenhouses lay it, and a concrete path across the rows' start, where the robot enters the
/// aisle. Colours are linear RGB in [0, 1]; both have to be colours that colour segmentation
/// does not label fruit (every command checks them with the plants' materials).
struct GroundLook {
  double film_r = 0.88, film_g = 0.89, film_b = 0.87;  ///< White ground film (slightly grey in shade).
  double path_r = 0.58, path_g = 0.57, path_b = 0.55;  ///< Concrete.
  double path_width_m = 1.2;  ///< Width of the concrete path across the rows' start (0: no path).
  /// Heating pipes: a pair of pipes along every row just above the floor, one each side of the
  /// row's centre line (a greenhouse's pipe-rail heating). Visual only: the base does not touch them.
  bool heating_pipes = false;
  double pipe_diameter_m = 0.051;  ///< 51 mm, the common pipe-rail tube.
  double pipe_height_m = 0.12;     ///< Height of the pipes' axes above the floor.
  double pipe_offset_m = 0.25;     ///< Distance of each pipe's axis from the row's centre line.
  double pipe_r = 0.82, pipe_g = 0.83, pipe_b = 0.80;  ///< White-painted steel.

  /// The keys of a world file's `ground`.
  template <class Archive>
  void visit(Archive& a) {
    a.tuple("film_rgb", {&film_r, &film_g, &film_b}, "[r, g, b]", limits::in(0.0, 1.0),
            "Colour of the ground film covering the floor (linear RGB, 0-1)");
    a.tuple("path_rgb", {&path_r, &path_g, &path_b}, "[r, g, b]", limits::in(0.0, 1.0),
            "Colour of the concrete path across the rows' start (linear RGB, 0-1)");
    a("path_width_m", path_width_m, limits::in(0.0, 20.0),
      "Width of the concrete path across the rows' start, where the robot enters the aisle [m]; 0: no path");
    a("heating_pipes", heating_pipes, "Lay a pair of heating pipes along every row, just above the floor");
    a("pipe_diameter_m", pipe_diameter_m, limits::in(0.005, 0.5), "With heating_pipes: outer diameter of each pipe [m]");
    a("pipe_height_m", pipe_height_m, limits::in(0.0, 2.0), "With heating_pipes: height of the pipes' axes above the floor [m]");
    a.check(pipe_height_m >= 0.5 * pipe_diameter_m, "pipe_height_m", "puts the pipes into the floor (must be >= pipe_diameter_m / 2)");
    a("pipe_offset_m", pipe_offset_m, limits::in(0.0, 5.0),
      "With heating_pipes: distance of each pipe's axis from its row's centre line (one pipe each side) [m]");
    a.tuple("pipe_rgb", {&pipe_r, &pipe_g, &pipe_b}, "[r, g, b]", limits::in(0.0, 1.0),
            "With heating_pipes: colour of the pipes (linear RGB, 0-1)");
  }
};

/// The sun over the greenhouse: one directional light. By default the same for every world
/// (as before this section existed: the scene does not change). With `per_seed` its direction
/// and brightness are drawn from the world's seed, as a greenhouse's light changes with the
/// hour and the weather, so colour segmentation meets varying light across world seeds.
struct Lighting {
  bool per_seed = false;
  double elevation_min_deg = 30.0, elevation_max_deg = 75.0;  ///< Sun above the horizon.
  double diffuse_min = 0.35, diffuse_max = 0.75;              ///< Sun brightness (MuJoCo diffuse, grey).

  /// The keys of a world file's `lighting`.
  template <class Archive>
  void visit(Archive& a) {
    a("per_seed", per_seed, "Draw the sun's direction and brightness from the world's seed (false: one fixed sun)");
    spec_detail::range(a, "sun_elevation_deg", elevation_min_deg, elevation_max_deg, limits::in(5.0, 90.0),
                       "With per_seed: the sun's elevation above the horizon [deg], drawn uniformly");
    spec_detail::range(a, "sun_diffuse", diffuse_min, diffuse_max, limits::in(0.0, 1.0),
                       "With per_seed: the sun's brightness (diffuse grey level, 0-1), drawn uniformly");
  }
  /// The sun of a world with seed `seed`: direction (towards the ground) and diffuse level.
  /// Without per_seed the fixed sun (-0.3, 0.2, -1), 0.55.
  void sun(std::uint64_t seed, Vec3* dir, double* diffuse) const;
};

/// An imported plant (a folder written by `canopy import-plant`) placed in the world, from
/// the world file's `plants` list: in a row slot (replacing that procedural plant, so stops
/// and scans along the rows cover it) or at a free position.
struct PlantPlacement {
  std::string import_dir;           ///< The plant folder, resolved (absolute).
  bool in_slot = false;
  int row = 0;                      ///< Slot: 0 is the row at y > 0, 1 the row at y < 0.
  int index = 0;                    ///< Slot: position along the row (0 = x_start_m).
  Vec2 position_m = Vec2::Zero();   ///< Free position of the base (when not in a slot).
  double yaw_rad = 0.0;             ///< Rotation about the base's vertical axis.
  double height_m = 0.0;            ///< From the folder's plant.yaml.
  double radius_m = 0.0;            ///< From the folder's plant.yaml: horizontal reach from the base.
};

/// Everything a world file holds. Defaults reproduce the paper's set-up: 8 plants in two
/// rows facing the aisle.
struct WorldSpec {
  std::string name = "default";
  std::string source_file;            ///< The YAML file it was read from ("" when built in code).
  std::uint64_t seed = 1;
  SemanticClasses classes;
  PartClasses part_classes;
  GroundLook ground;
  Lighting lighting;
  RowLayout rows;
  PlantParams plant;
  CameraIntrinsics camera;
  BasePose robot_start;               ///< Base pose at the start of the aisle.
  double gt_point_spacing_m = 0.003;  ///< Ground-truth fruit surface sample spacing.
  std::vector<PlantPlacement> placements;  ///< Imported plants (world file key `plants`).

  /// Every key of a world file but `plants` (read and written beside it: imported folders
  /// are found on disk).
  template <class Archive>
  void visit(Archive& a) {
    a("name", name, "Name of the world in result folders and plots");
    a.check(spec_detail::valid_world_name(name), "name", "must be 1-64 letters, digits, '_', '-' or '.' (no '..', no '/')");
    a("seed", seed, limits::non_negative(), "Seed of every plant's shape and place");
    a("classes", classes.names, "Semantic classes, background first");
    a("target_class", classes.target, "The class the metrics count (fruit)");
    a.section("part_classes", part_classes, "Which class each kind of geometry carries");
    a.section("ground", ground, "What the floor looks like: ground film, a concrete path, heating pipes");
    a.section("lighting", lighting, "The sun: fixed, or drawn per world seed");
    a.section("rows", rows, "Plants in rows along the aisle");
    a.section("plant", plant, "Ranges each procedural plant draws its shape from");
    a.section("camera", camera, "The wrist camera (rendered: fx = fy, principal point at the centre)");
    a.tuple("robot_start", {&robot_start.x_m, &robot_start.y_m, &robot_start.yaw_rad}, "[x, y, yaw]", limits::finite(),
            "Base pose at the start of the aisle [m, m, rad]");
    a.check(std::abs(robot_start.x_m) <= kMaxWorldExtentM && std::abs(robot_start.y_m) <= kMaxWorldExtentM,
            "robot_start", "lies outside the world (at most 1000 m from the origin)");
    a("gt_point_spacing_m", gt_point_spacing_m, limits::at_least(0.0005),
      "Spacing of the ground-truth fruit surface points [m]");
  }

  /// Reads and validates a world file; throws InputError naming file, key and value.
  static WorldSpec load(const std::string& path);
  /// Throws InputError (naming source_file) when a value is out of range.
  void validate() const;
  /// Class index of a part kind ("stem", "leaf", "fruit", ...).
  int class_of(const std::string& part) const;
  /// True when fruits of `color` are targets (plant.ripe_colors).
  bool is_ripe(const std::string& color) const;
  int plant_count() const;
  /// The placement in row slot (row, index), or nullptr when that slot is procedural.
  const PlantPlacement* placement_in_slot(int row, int index) const;
  /// How far a plant may reach sideways from its nominal row position: position jitter plus
  /// the longest petiole and leaf blade.
  double plant_reach_m() const;
  /// Throws InputError (naming source_file and rows.row_offset_m) unless a base of half width
  /// `base_half_width_m` on the aisle's centre line keeps `clearance_m` from every plant's reach.
  void check_aisle(double base_half_width_m, double clearance_m) const;
  /// The base's reach: its planar joints' ranges [lower, upper] (m) and the arm's offset along
  /// the base's x axis (a stop at arm x = s puts the base at s - arm_x_m).
  struct BaseRange {
    double x_lower_m = 0.0, x_upper_m = 0.0, y_lower_m = 0.0, y_upper_m = 0.0, arm_x_m = 0.0;
    std::string x_joint = "base_x", y_joint = "base_y", source;  ///< Names in messages (source: the URDF).
  };
  /// Throws InputError (naming source_file and the key) unless the base, within `range`, can
  /// stand beside every plant of the rows (the arm over the first and the last plant) and
  /// start at robot_start.
  void check_base_range(const BaseRange& range) const;
  /// The resolved parameters as JSON, with the keys of a world file (JSON is YAML, so
  /// load() reads a saved copy back to the same spec).
  nlohmann::json to_json() const;
};

}  // namespace canopy::world
