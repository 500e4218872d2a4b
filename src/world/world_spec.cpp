#include "canopy/world/world_spec.h"

#include <cmath>
#include <sstream>

#include <filesystem>
#include <set>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/world/plant_import.h"

namespace canopy::world {

namespace {

// Reads a [min, max] pair; both must be finite, min <= max and, with `positive`, > 0.
void read_range(YamlReader& y, const std::string& key, double* lo, double* hi, bool positive = true) {
  if (!y.has(key)) return;
  std::vector<double> v;
  try {
    v = y.require<std::vector<double>>(key);
  } catch (const InputError&) {
    y.fail(key, "must be a pair [min, max] of numbers");
  }
  y.check(v.size() == 2, key, "must be a pair [min, max]");
  y.check(std::isfinite(v[0]) && std::isfinite(v[1]), key, "must be finite");
  y.check(v[0] <= v[1], key, "must have min <= max");
  if (positive) y.check(v[0] > 0.0, key, "must be positive");
  *lo = v[0];
  *hi = v[1];
}

void read_int_range(YamlReader& y, const std::string& key, int* lo, int* hi, int max) {
  if (!y.has(key)) return;
  std::vector<int> v;
  try {
    v = y.require<std::vector<int>>(key);
  } catch (const InputError&) {
    y.fail(key, "must be a pair [min, max] of whole numbers");
  }
  y.check(v.size() == 2 && v[0] >= 0 && v[0] <= v[1], key, "must be a pair [min, max] with 0 <= min <= max");
  y.check(v[1] <= max, key, "must be a pair [min, max] with max <= " + std::to_string(max) + " (a plausible plant)");
  *lo = v[0];
  *hi = v[1];
}

double read_positive(YamlReader& y, const std::string& key, double fallback) {
  const double v = y.get(key, fallback);
  y.check(std::isfinite(v) && v > 0.0, key, "must be > 0");
  return v;
}

// A plant folder named in a world file: as given (current folder or canopy's source tree),
// else relative to the world file's folder.
std::string resolve_plant_dir(const std::string& dir, const std::string& world_file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const std::string found = find_data_file(dir);
  if (fs::is_directory(found, ec)) return fs::absolute(found).lexically_normal().string();
  const fs::path beside = fs::path(world_file).parent_path() / dir;
  if (!fs::path(dir).is_absolute() && fs::is_directory(beside, ec)) return fs::absolute(beside).lexically_normal().string();
  return "";
}

// The world file's `plants` list: imported plants in row slots or at free positions.
std::vector<PlantPlacement> read_placements(YamlReader& y, const std::string& path) {
  std::vector<PlantPlacement> out;
  if (!y.has("plants")) return out;
  YAML::Node list = y.require<YAML::Node>("plants");
  if (!list.IsSequence()) y.fail("plants", "must be a list of {plant: {import: FOLDER}, slot: [row, index] or position: [x, y], yaw_deg}");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = "plants[" + std::to_string(i) + "]";
    YamlReader e(list[i], path, where);
    PlantPlacement pl;
    YamlReader plant = e.child("plant");
    const std::string dir = plant.require<std::string>("import");
    plant.finish();
    pl.import_dir = resolve_plant_dir(dir, path);
    if (pl.import_dir.empty())
      throw InputError(path + ": key '" + where + ".plant.import': value '" + dir + "' is not a plant folder");
    read_plant_size(pl.import_dir, &pl.height_m, &pl.radius_m);
    e.check(e.has("slot") != e.has("position"), "slot", "give exactly one of slot: [row, index] and position: [x, y]");
    if (e.has("slot")) {
      std::vector<int> v;
      try {
        v = e.require<std::vector<int>>("slot");
      } catch (const InputError&) {
        e.fail("slot", "must be [row, index] (whole numbers)");
      }
      e.check(v.size() == 2, "slot", "must be [row, index]");
      pl.in_slot = true;
      pl.row = v[0];
      pl.index = v[1];
    } else {
      std::vector<double> v;
      try {
        v = e.require<std::vector<double>>("position");
      } catch (const InputError&) {
        e.fail("position", "must be [x, y] in metres");
      }
      e.check(v.size() == 2 && std::isfinite(v[0]) && std::isfinite(v[1]), "position", "must be [x, y] (finite)");
      e.check(std::abs(v[0]) <= kMaxWorldExtentM && std::abs(v[1]) <= kMaxWorldExtentM, "position",
              "lies outside the world (at most " + std::to_string(kMaxWorldExtentM) + " m from the origin)");
      pl.position_m = Vec2(v[0], v[1]);
    }
    const double yaw_deg = e.get("yaw_deg", 0.0);
    e.check(std::isfinite(yaw_deg), "yaw_deg", "must be finite");
    pl.yaw_rad = yaw_deg * M_PI / 180.0;
    e.finish();
    out.push_back(pl);
  }
  return out;
}

}  // namespace

WorldSpec WorldSpec::load(const std::string& path) {
  YamlReader y = YamlReader::load_file(path);
  WorldSpec s;
  s.source_file = path;
  s.name = y.get("name", s.name);
  // The name goes into folder and file names of results and into plots.
  y.check(!s.name.empty() && s.name.size() <= 64 &&
              s.name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") ==
                  std::string::npos &&
              s.name.find("..") == std::string::npos,
          "name", "must be 1-64 letters, digits, '_', '-' or '.' (no '..', no '/')");
  const long long seed = y.get<long long>("seed", static_cast<long long>(s.seed));
  y.check(seed >= 0, "seed", "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed);
  s.classes.names = y.get("classes", s.classes.names);
  s.classes.target = y.get("target_class", s.classes.target);

  YamlReader pc = y.child("part_classes");
  s.part_classes.ground = pc.get("ground", s.part_classes.ground);
  s.part_classes.robot = pc.get("robot", s.part_classes.robot);
  s.part_classes.stem = pc.get("stem", s.part_classes.stem);
  s.part_classes.petiole = pc.get("petiole", s.part_classes.petiole);
  s.part_classes.leaf = pc.get("leaf", s.part_classes.leaf);
  s.part_classes.peduncle = pc.get("peduncle", s.part_classes.peduncle);
  s.part_classes.fruit = pc.get("fruit", s.part_classes.fruit);
  s.part_classes.unripe_fruit = pc.get("unripe_fruit", s.part_classes.unripe_fruit);
  pc.finish();

  YamlReader r = y.child("rows");
  s.rows.rows = r.get("rows", s.rows.rows);
  r.check(s.rows.rows == 1 || s.rows.rows == 2, "rows", "must be 1 or 2");
  s.rows.plants_per_row = r.get("plants_per_row", s.rows.plants_per_row);
  r.check(s.rows.plants_per_row >= 1 && s.rows.plants_per_row <= 1000, "plants_per_row", "must be in 1..1000");
  s.rows.plant_spacing_m = read_positive(r, "plant_spacing_m", s.rows.plant_spacing_m);
  s.rows.row_offset_m = read_positive(r, "row_offset_m", s.rows.row_offset_m);
  s.rows.x_start_m = r.get("x_start_m", s.rows.x_start_m);
  r.check(std::isfinite(s.rows.x_start_m), "x_start_m", "must be finite");
  s.rows.position_jitter_m = r.get("position_jitter_m", s.rows.position_jitter_m);
  r.check(s.rows.position_jitter_m >= 0.0 && s.rows.position_jitter_m < 0.5 * s.rows.plant_spacing_m,
          "position_jitter_m", "must be in [0, plant_spacing_m / 2)");
  r.finish();

  YamlReader p = y.child("plant");
  PlantParams& pp = s.plant;
  read_range(p, "height_m", &pp.height_min_m, &pp.height_max_m);
  read_range(p, "stem_diameter_m", &pp.stem_diameter_min_m, &pp.stem_diameter_max_m);
  read_range(p, "v_angle_deg", &pp.v_angle_min_deg, &pp.v_angle_max_deg, false);
  read_int_range(p, "leaves_per_stem", &pp.leaves_per_stem_min, &pp.leaves_per_stem_max, kMaxLeavesPerStem);
  read_range(p, "leaf_length_m", &pp.leaf_length_min_m, &pp.leaf_length_max_m);
  pp.leaf_width_ratio = read_positive(p, "leaf_width_ratio", pp.leaf_width_ratio);
  read_range(p, "petiole_length_m", &pp.petiole_length_min_m, &pp.petiole_length_max_m);
  read_int_range(p, "fruits", &pp.fruits_min, &pp.fruits_max, kMaxFruitsPerPlant);
  read_range(p, "fruit_zone", &pp.fruit_zone_min, &pp.fruit_zone_max);
  pp.blocky_fraction = p.get("blocky_fraction", pp.blocky_fraction);
  p.check(pp.blocky_fraction >= 0.0 && pp.blocky_fraction <= 1.0, "blocky_fraction", "must be in [0, 1]");
  read_range(p, "blocky_width_m", &pp.blocky_width_min_m, &pp.blocky_width_max_m);
  read_range(p, "blocky_length_m", &pp.blocky_length_min_m, &pp.blocky_length_max_m);
  read_range(p, "conical_width_m", &pp.conical_width_min_m, &pp.conical_width_max_m);
  read_range(p, "conical_length_m", &pp.conical_length_min_m, &pp.conical_length_max_m);
  if (p.has("fruit_colors")) {
    try {
      pp.fruit_colors = p.require<std::map<std::string, double>>("fruit_colors");
    } catch (const InputError&) {
      p.fail("fruit_colors", "must map colour names to weights");
    }
  }
  if (p.has("ripe_colors")) {
    try {
      pp.ripe_colors = p.require<std::vector<std::string>>("ripe_colors");
    } catch (const InputError&) {
      p.fail("ripe_colors", "must be a list of colour names");
    }
  }
  p.finish();
  auto known_color = [](const std::string& c) { return c == "red" || c == "yellow" || c == "green" || c == "orange"; };
  for (const std::string& name : pp.ripe_colors)
    if (!known_color(name))
      throw InputError(path + ": key 'plant.ripe_colors': unknown colour '" + name + "' (use red, yellow, orange, green)");
  for (const auto& [name, w] : pp.fruit_colors) {
    if (!known_color(name))
      throw InputError(path + ": key 'plant.fruit_colors." + name + "': unknown colour (use red, yellow, orange, green)");
    if (!(w >= 0.0) || !std::isfinite(w))
      throw InputError(path + ": key 'plant.fruit_colors." + name + "': value '" + std::to_string(w) + "' must be >= 0");
  }

  YamlReader c = y.child("camera");
  CameraIntrinsics& K = s.camera;
  K.width_px = c.get("width_px", K.width_px);
  K.height_px = c.get("height_px", K.height_px);
  K.fx_px = c.get("fx_px", K.fx_px);
  K.fy_px = c.get("fy_px", K.fy_px);
  K.cx_px = c.get("cx_px", 0.5 * K.width_px);
  K.cy_px = c.get("cy_px", 0.5 * K.height_px);
  K.min_range_m = c.get("min_range_m", K.min_range_m);
  K.max_range_m = c.get("max_range_m", K.max_range_m);
  K.depth_noise_k = c.get("depth_noise_k", K.depth_noise_k);
  c.finish();

  if (y.has("robot_start")) {
    const auto v = y.require<std::vector<double>>("robot_start");
    y.check(v.size() == 3 && std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]), "robot_start",
            "must be [x, y, yaw] (finite)");
    s.robot_start = BasePose{v[0], v[1], v[2]};
  }
  s.gt_point_spacing_m = read_positive(y, "gt_point_spacing_m", s.gt_point_spacing_m);
  y.check(s.gt_point_spacing_m >= 0.0005, "gt_point_spacing_m", "must be >= 0.0005 (too many points otherwise)");
  s.placements = read_placements(y, path);
  y.finish();
  s.validate();
  return s;
}

void WorldSpec::validate() const {
  const std::string where = source_file.empty() ? std::string("world") : source_file;
  classes.validate(where);
  camera.validate(where);
  for (const std::string part : {"ground", "robot", "stem", "petiole", "leaf", "peduncle", "fruit", "unripe_fruit"}) {
    if (class_of(part) < 0)
      throw InputError(where + ": key 'part_classes." + part + "': its class is not in the class list");
  }
  double total = 0.0;
  for (const auto& kv : plant.fruit_colors) total += kv.second;
  if (plant.fruits_max > 0 && !(total > 0.0))
    throw InputError(where + ": key 'plant.fruit_colors': the weights must not all be zero");
  if (plant.fruit_zone_max > 1.0)
    throw InputError(where + ": key 'plant.fruit_zone': must lie within (0, 1]");
  // Sizes beyond any greenhouse are typos (1e30 for 1.3) and would make absurd meshes.
  const std::pair<const char*, double> sizes[] = {
      {"plant.height_m", plant.height_max_m},
      {"plant.stem_diameter_m", plant.stem_diameter_max_m},
      {"plant.leaf_length_m", plant.leaf_length_max_m},
      {"plant.leaf_width_ratio", plant.leaf_width_ratio * plant.leaf_length_max_m},
      {"plant.petiole_length_m", plant.petiole_length_max_m},
      {"plant.blocky_width_m", plant.blocky_width_max_m},
      {"plant.blocky_length_m", plant.blocky_length_max_m},
      {"plant.conical_width_m", plant.conical_width_max_m},
      {"plant.conical_length_m", plant.conical_length_max_m}};
  for (const auto& [key, v] : sizes)
    if (!(std::abs(v) <= kMaxPlantSizeM))
      throw InputError(where + ": key '" + key + "': a size of " + std::to_string(v) + " m is larger than a plant (at most " +
                       std::to_string(kMaxPlantSizeM) + " m)");
  const double row_length_m = rows.plant_spacing_m * (rows.plants_per_row - 1);
  const std::pair<const char*, double> extents[] = {{"rows.plant_spacing_m", row_length_m},
                                                    {"rows.row_offset_m", rows.row_offset_m},
                                                    {"rows.x_start_m", rows.x_start_m},
                                                    {"rows.x_start_m", rows.x_start_m + row_length_m},
                                                    {"robot_start", robot_start.x_m},
                                                    {"robot_start", robot_start.y_m}};
  for (const auto& [key, v] : extents)
    if (!(std::abs(v) <= kMaxWorldExtentM))
      throw InputError(where + ": key '" + key + "': the world would reach " + std::to_string(v) +
                       " m from the origin (at most " + std::to_string(kMaxWorldExtentM) + " m)");
  if (2.0 * rows.row_offset_m < 0.5)
    throw InputError(where + ": key 'rows.row_offset_m': rows closer than 0.25 m to the aisle leave no room for the robot");
  std::set<std::pair<int, int>> slots;
  for (size_t i = 0; i < placements.size(); ++i) {
    const PlantPlacement& p = placements[i];
    const std::string key = where + ": key 'plants[" + std::to_string(i) + "]";
    if (!p.in_slot) continue;
    if (p.row < 0 || p.row >= rows.rows || p.index < 0 || p.index >= rows.plants_per_row)
      throw InputError(key + ".slot': [" + std::to_string(p.row) + ", " + std::to_string(p.index) +
                       "] is not a slot of the rows (row 0.." + std::to_string(rows.rows - 1) + ", index 0.." +
                       std::to_string(rows.plants_per_row - 1) + ")");
    if (!slots.insert({p.row, p.index}).second)
      throw InputError(key + ".slot': slot [" + std::to_string(p.row) + ", " + std::to_string(p.index) + "] is taken twice");
  }
}

int WorldSpec::plant_count() const {
  int n = rows.rows * rows.plants_per_row;
  for (const auto& p : placements) n += p.in_slot ? 0 : 1;
  return n;
}

const PlantPlacement* WorldSpec::placement_in_slot(int row, int index) const {
  for (const auto& p : placements)
    if (p.in_slot && p.row == row && p.index == index) return &p;
  return nullptr;
}

double WorldSpec::plant_reach_m() const {
  return rows.position_jitter_m + plant.petiole_length_max_m + plant.leaf_length_max_m;
}

void WorldSpec::check_aisle(double base_half_width_m, double clearance_m) const {
  const double free_half_width = rows.row_offset_m - plant_reach_m();
  const double needed = base_half_width_m + clearance_m;
  if (free_half_width < needed) {
    std::ostringstream os;
    os << (source_file.empty() ? std::string("world") : source_file) << ": key 'rows.row_offset_m': value '"
       << rows.row_offset_m << "' leaves an aisle " << 2.0 * free_half_width
       << " m wide (rows minus the plants' reach of " << plant_reach_m() << " m each side), narrower than the base ("
       << 2.0 * base_half_width_m << " m) plus " << clearance_m
       << " m clearance each side (robot.yaml aisle_clearance_m); row_offset_m must be >= "
       << needed + plant_reach_m();
    throw InputError(os.str());
  }
  // Imported plants reach as far as their own radius from their base.
  for (size_t i = 0; i < placements.size(); ++i) {
    const PlantPlacement& p = placements[i];
    const double y = p.in_slot ? rows.row_offset_m : std::abs(p.position_m.y());
    if (y - p.radius_m < needed) {
      std::ostringstream os;
      os << (source_file.empty() ? std::string("world") : source_file) << ": key 'plants[" << i
         << "]': the imported plant " << p.import_dir << " reaches " << p.radius_m << " m from its base, "
         << y - p.radius_m << " m from the aisle's centre line; the base needs " << needed
         << " m (half width plus clearance)";
      throw InputError(os.str());
    }
  }
}

namespace {
nlohmann::json placements_json(const std::vector<PlantPlacement>& placements) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : placements) {
    nlohmann::json e = {{"plant", {{"import", p.import_dir}}}, {"yaw_deg", p.yaw_rad * 180.0 / M_PI}};
    if (p.in_slot) e["slot"] = {p.row, p.index};
    else e["position"] = {p.position_m.x(), p.position_m.y()};
    out.push_back(e);
  }
  return out;
}
}  // namespace

nlohmann::json WorldSpec::to_json() const {
  using nlohmann::json;
  const PlantParams& p = plant;
  json colors = json::object();
  for (const auto& [name, w] : p.fruit_colors) colors[name] = w;
  return {
      {"name", name},
      {"seed", seed},
      {"classes", classes.names},
      {"target_class", classes.target},
      {"part_classes",
       {{"ground", part_classes.ground}, {"robot", part_classes.robot}, {"stem", part_classes.stem},
        {"petiole", part_classes.petiole}, {"leaf", part_classes.leaf}, {"peduncle", part_classes.peduncle},
        {"fruit", part_classes.fruit}, {"unripe_fruit", part_classes.unripe_fruit}}},
      {"rows",
       {{"rows", rows.rows}, {"plants_per_row", rows.plants_per_row}, {"plant_spacing_m", rows.plant_spacing_m},
        {"row_offset_m", rows.row_offset_m}, {"x_start_m", rows.x_start_m},
        {"position_jitter_m", rows.position_jitter_m}}},
      {"plant",
       {{"height_m", {p.height_min_m, p.height_max_m}},
        {"stem_diameter_m", {p.stem_diameter_min_m, p.stem_diameter_max_m}},
        {"v_angle_deg", {p.v_angle_min_deg, p.v_angle_max_deg}},
        {"leaves_per_stem", {p.leaves_per_stem_min, p.leaves_per_stem_max}},
        {"leaf_length_m", {p.leaf_length_min_m, p.leaf_length_max_m}},
        {"leaf_width_ratio", p.leaf_width_ratio},
        {"petiole_length_m", {p.petiole_length_min_m, p.petiole_length_max_m}},
        {"fruits", {p.fruits_min, p.fruits_max}},
        {"fruit_zone", {p.fruit_zone_min, p.fruit_zone_max}},
        {"blocky_fraction", p.blocky_fraction},
        {"blocky_width_m", {p.blocky_width_min_m, p.blocky_width_max_m}},
        {"blocky_length_m", {p.blocky_length_min_m, p.blocky_length_max_m}},
        {"conical_width_m", {p.conical_width_min_m, p.conical_width_max_m}},
        {"conical_length_m", {p.conical_length_min_m, p.conical_length_max_m}},
        {"fruit_colors", colors},
        {"ripe_colors", p.ripe_colors}}},
      {"camera",
       {{"width_px", camera.width_px}, {"height_px", camera.height_px}, {"fx_px", camera.fx_px},
        {"fy_px", camera.fy_px}, {"cx_px", camera.cx_px}, {"cy_px", camera.cy_px},
        {"min_range_m", camera.min_range_m}, {"max_range_m", camera.max_range_m},
        {"depth_noise_k", camera.depth_noise_k}}},
      {"robot_start", {robot_start.x_m, robot_start.y_m, robot_start.yaw_rad}},
      {"gt_point_spacing_m", gt_point_spacing_m},
      {"plants", placements_json(placements)},
  };
}

int WorldSpec::class_of(const std::string& part) const {
  const std::string* name = nullptr;
  if (part == "ground") name = &part_classes.ground;
  else if (part == "robot") name = &part_classes.robot;
  else if (part == "stem") name = &part_classes.stem;
  else if (part == "petiole") name = &part_classes.petiole;
  else if (part == "leaf") name = &part_classes.leaf;
  else if (part == "peduncle") name = &part_classes.peduncle;
  else if (part == "fruit") name = &part_classes.fruit;
  else if (part == "unripe_fruit") name = &part_classes.unripe_fruit;
  return name ? classes.index_of(*name) : -1;
}

bool WorldSpec::is_ripe(const std::string& color) const {
  for (const std::string& c : plant.ripe_colors)
    if (c == color) return true;
  return false;
}

}  // namespace canopy::world
