#pragma once
// A greenhouse world as written in worlds/<name>.yaml: rows of procedurally generated
// sweet-pepper plants along an aisle, the semantic classes, the camera and the robot start.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
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

/// Plants in rows parallel to the world x axis, on both sides of an aisle along y = 0.
struct RowLayout {
  int rows = 2;                    ///< 1 (left of the aisle, y > 0) or 2 (both sides).
  int plants_per_row = 4;
  double plant_spacing_m = 0.5;    ///< Along the row.
  double row_offset_m = 0.75;      ///< |y| of each row's centre line.
  double x_start_m = 0.0;          ///< x of the first plant of each row.
  double position_jitter_m = 0.03; ///< Uniform jitter of each plant's position.
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
  RowLayout rows;
  PlantParams plant;
  CameraIntrinsics camera;
  BasePose robot_start;               ///< Base pose at the start of the aisle.
  double gt_point_spacing_m = 0.003;  ///< Ground-truth fruit surface sample spacing.
  std::vector<PlantPlacement> placements;  ///< Imported plants (world file key `plants`).

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
  /// The resolved parameters as JSON, with the keys of a world file (JSON is YAML, so
  /// load() reads a saved copy back to the same spec).
  nlohmann::json to_json() const;
};

}  // namespace canopy::world
