#include "canopy/world/world_spec.h"

#include <cmath>
#include <sstream>

#include <filesystem>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/world/plant_import.h"

namespace canopy::world {

namespace spec_detail {

bool known_fruit_color(const std::string& name) {
  return name == "red" || name == "yellow" || name == "green" || name == "orange";
}

bool known_fruit_colors(const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (!known_fruit_color(n)) return false;
  return true;
}

bool valid_color_weights(const std::map<std::string, double>& weights) {
  for (const auto& [name, w] : weights)
    if (!known_fruit_color(name) || !(w >= 0.0) || !std::isfinite(w)) return false;
  return true;
}

bool valid_world_name(const std::string& name) {
  // The name goes into folder and file names of results and into plots.
  return !name.empty() && name.size() <= 64 &&
         name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") ==
             std::string::npos &&
         name.find("..") == std::string::npos;
}

}  // namespace spec_detail

namespace {

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

// A world file's camera keeps its principal point at the image centre unless it names one
// (the renderer demands it there): a world giving only width_px gets cx_px = width_px / 2.
void centre_principal_point(YamlReader& y, CameraIntrinsics* K) {
  YamlReader c = y.child("camera");
  try {
    if (c.has("width_px") && !c.has("cx_px")) K->cx_px = 0.5 * c.require<double>("width_px");
    if (c.has("height_px") && !c.has("cy_px")) K->cy_px = 0.5 * c.require<double>("height_px");
  } catch (const InputError&) {
    // Not a number: reading the camera through its visit() names the key.
  }
}

}  // namespace

WorldSpec WorldSpec::load(const std::string& path) {
  YamlReader y = YamlReader::load_file(path);
  WorldSpec s;
  s.source_file = path;
  centre_principal_point(y, &s.camera);
  read_params(y, s);
  s.placements = read_placements(y, path);
  y.finish();
  s.validate();
  return s;
}

void WorldSpec::validate() const {
  const std::string where = source_file.empty() ? std::string("world") : source_file;
  validate_params(*this, where);
  classes.validate(where);
  camera.validate(where);
  for (const std::string part : {"ground", "robot", "stem", "petiole", "leaf", "peduncle", "fruit", "unripe_fruit", "trellis"}) {
    if (class_of(part) < 0)
      throw InputError(where + ": key 'part_classes." + part + "': its class is not in the class list");
  }
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

void Lighting::sun(std::uint64_t seed, Vec3* dir, double* diffuse) const {
  if (!per_seed) {
    *dir = Vec3(-0.3, 0.2, -1.0);
    *diffuse = 0.55;
    return;
  }
  Rng rng(mix_seed(seed, 0x5117));  // its own stream: the plants draw nothing less or more
  const double azimuth = rng.uniform(0.0, 2.0 * M_PI);
  const double elevation = rng.uniform(elevation_min_deg, elevation_max_deg) * M_PI / 180.0;
  *diffuse = rng.uniform(diffuse_min, diffuse_max);
  *dir = -Vec3(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
}

double WorldSpec::plant_reach_m() const {
  return rows.position_jitter_m + plant.petiole_length_max_m + plant.leaf_length_max_m;
}

void WorldSpec::check_base_range(const BaseRange& r) const {
  const std::string file = source_file.empty() ? std::string("world") : source_file;
  const auto range = [](double lo, double hi) {
    std::ostringstream os;
    os << "[" << lo << ", " << hi << "] m";
    return os.str();
  };
  // The arm stands over the first and the last plant of the rows; the base behind it.
  const double first = rows.x_start_m, last = rows.x_start_m + rows.plant_spacing_m * (rows.plants_per_row - 1);
  const double base_first = first - r.arm_x_m, base_last = last - r.arm_x_m;
  if (base_first < r.x_lower_m || base_last > r.x_upper_m) {
    std::ostringstream os;
    os << file << ": key 'rows.x_start_m': rows from x = " << first << " to " << last << " m need the base at x = "
       << base_first << " to " << base_last << " m, beyond its joint '" << r.x_joint << "' range "
       << range(r.x_lower_m, r.x_upper_m) << " (" << r.source << "); the rows' plants must lie within x = "
       << r.x_lower_m + r.arm_x_m << " to " << r.x_upper_m + r.arm_x_m << " m";
    throw InputError(os.str());
  }
  if (robot_start.x_m < r.x_lower_m || robot_start.x_m > r.x_upper_m || robot_start.y_m < r.y_lower_m ||
      robot_start.y_m > r.y_upper_m) {
    std::ostringstream os;
    os << file << ": key 'robot_start': [" << robot_start.x_m << ", " << robot_start.y_m
       << "] lies outside the base's joint ranges ('" << r.x_joint << "' " << range(r.x_lower_m, r.x_upper_m) << ", '"
       << r.y_joint << "' " << range(r.y_lower_m, r.y_upper_m) << ", " << r.source << ")";
    throw InputError(os.str());
  }
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
  // The heating pipes nearer the aisle lie under the plants, never in the base's way.
  if (ground.heating_pipes && rows.row_offset_m - ground.pipe_offset_m - 0.5 * ground.pipe_diameter_m < needed) {
    std::ostringstream os;
    os << (source_file.empty() ? std::string("world") : source_file) << ": key 'ground.pipe_offset_m': value '"
       << ground.pipe_offset_m << "' puts the heating pipes " << rows.row_offset_m - ground.pipe_offset_m
       << " m from the aisle's centre line, in the base's way (it needs " << needed
       << " m: half width plus clearance); pipe_offset_m must be <= "
       << rows.row_offset_m - needed - 0.5 * ground.pipe_diameter_m;
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
  nlohmann::json j = params_to_json(*this);
  j["plants"] = placements_json(placements);
  return j;
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
  else if (part == "trellis") name = &part_classes.trellis;
  return name ? classes.index_of(*name) : -1;
}

bool WorldSpec::is_ripe(const std::string& color) const {
  for (const std::string& c : plant.ripe_colors)
    if (c == color) return true;
  return false;
}

}  // namespace canopy::world
