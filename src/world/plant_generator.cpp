// Procedural sweet-pepper plants (docs/background/plants.md): a short trunk splitting into two
// stems in a V, alternate leaves on petioles, and blocky or conical fruits hanging from
// peduncles in the fruit zone. Every part is a closed low-poly mesh in world coordinates.

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <map>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/world/plant_import.h"
#include "canopy/world/world.h"

namespace canopy::world {

namespace {

constexpr double kDeg = M_PI / 180.0;

struct Color {
  float r, g, b;
};

Color fruit_color(const std::string& name) {
  if (name == "red") return {0.75f, 0.06f, 0.05f};
  if (name == "yellow") return {0.95f, 0.78f, 0.08f};
  if (name == "orange") return {0.95f, 0.45f, 0.05f};
  return {0.12f, 0.40f, 0.08f};  // green (unripe)
}

void set_rgba(PlantPart* p, Color c) {
  p->rgba[0] = c.r;
  p->rgba[1] = c.g;
  p->rgba[2] = c.b;
  p->rgba[3] = 1.f;
}

Color jitter(Rng& rng, Color c, float amount) {
  auto j = [&](float v) { return std::clamp(v + static_cast<float>(rng.uniform(-amount, amount)), 0.f, 1.f); };
  return {j(c.r), j(c.g), j(c.b)};
}

// Closed, thin leaf blade in its local frame: base at the origin, blade along +x, upper
// side towards +z. `fold` raises the edges along the midrib, `droop` bends the tip down.
TriMesh make_leaf(double length, double width, double fold, double droop, double thickness) {
  constexpr int ns = 6;  // stations along the blade
  constexpr int nt = 5;  // samples across, t in [-1, 1]
  TriMesh m;
  auto half_width = [&](double s) {
    // Ovate outline: widest at about a third of the length, narrow at base and tip.
    return std::max(0.0015, 0.5 * width * std::pow(std::sin(M_PI * std::pow(s, 0.75)), 0.9));
  };
  for (int side = 0; side < 2; ++side) {
    const double dz = side == 0 ? 0.5 * thickness : -0.5 * thickness;
    for (int i = 0; i <= ns; ++i) {
      const double s = static_cast<double>(i) / ns;
      const double x = s * length, w = half_width(s);
      for (int j = 0; j < nt; ++j) {
        const double t = -1.0 + 2.0 * j / (nt - 1);
        m.vertices.push_back(Vec3(x, t * w, fold * std::abs(t) * w - droop * x * x + dz));
      }
    }
  }
  const int per_side = (ns + 1) * nt;
  auto top = [&](int i, int j) { return i * nt + j; };
  auto bot = [&](int i, int j) { return per_side + i * nt + j; };
  for (int i = 0; i < ns; ++i)
    for (int j = 0; j + 1 < nt; ++j) {
      m.faces.push_back({top(i, j), top(i + 1, j), top(i + 1, j + 1)});
      m.faces.push_back({top(i, j), top(i + 1, j + 1), top(i, j + 1)});
      m.faces.push_back({bot(i, j), bot(i + 1, j + 1), bot(i + 1, j)});
      m.faces.push_back({bot(i, j), bot(i, j + 1), bot(i + 1, j + 1)});
    }
  // Rim: the outline walked counter-clockwise seen from +z, stitched top to bottom.
  std::vector<std::pair<int, int>> loop;
  for (int i = 0; i <= ns; ++i) loop.push_back({i, 0});
  for (int j = 1; j < nt; ++j) loop.push_back({ns, j});
  for (int i = ns - 1; i >= 0; --i) loop.push_back({i, nt - 1});
  for (int j = nt - 2; j >= 1; --j) loop.push_back({0, j});
  for (size_t k = 0; k < loop.size(); ++k) {
    const auto a = loop[k], b = loop[(k + 1) % loop.size()];
    const int at = top(a.first, a.second), ab = bot(a.first, a.second);
    const int bt = top(b.first, b.second), bb = bot(b.first, b.second);
    m.faces.push_back({at, ab, bb});
    m.faces.push_back({at, bb, bt});
  }
  return m;
}

// Fruit profile (r, z) from the top pole (z = 0) down to the bottom pole (z = -length).
std::vector<Vec2> fruit_profile(bool blocky, double width, double length) {
  const double R = 0.5 * width;
  const int n = 11;
  std::vector<Vec2> p;
  for (int i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / (n - 1);
    double r;
    if (blocky) {
      r = R * std::pow(std::sin(M_PI * t), 0.35) * (1.0 - 0.12 * t);
    } else {
      r = R * std::sqrt(std::sin(0.5 * M_PI * std::min(1.0, t / 0.22))) * std::pow(1.0 - t, 0.85);
    }
    p.push_back(Vec2(i == 0 || i == n - 1 ? 0.0 : r, -t * length));
  }
  return p;
}

// Rotation taking +z to `dir` (any roll).
Mat3 frame_with_z(const Vec3& dir) {
  const Vec3 z = dir.normalized();
  const Vec3 x = z.unitOrthogonal();
  Mat3 R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return R;
}

struct Stem {
  std::vector<Vec3> points;
  std::vector<double> radii;
  // Point on the stem at height z (linear along the polyline).
  Vec3 at_height(double z) const {
    for (size_t i = 0; i + 1 < points.size(); ++i) {
      if (z <= points[i + 1].z() || i + 2 == points.size()) {
        const double t = std::clamp((z - points[i].z()) / (points[i + 1].z() - points[i].z()), 0.0, 1.0);
        return points[i] + t * (points[i + 1] - points[i]);
      }
    }
    return points.back();
  }
};

std::string pick_color(Rng& rng, const std::map<std::string, double>& weights) {
  double total = 0.0;
  for (const auto& kv : weights) total += kv.second;
  double u = rng.uniform() * total;
  for (const auto& kv : weights) {
    if (u < kv.second) return kv.first;
    u -= kv.second;
  }
  return weights.rbegin()->first;
}

// A procedural plant being built: the world's settings, the plant's random stream (every
// stage draws from it in turn, so the stages' order is the plant's seed), its parts so far.
struct PlantBuild {
  const WorldSpec& spec;
  Rng rng;
  Plant plant;
  std::string prefix;  // of the parts' names: "p<index>_"

  // Adds the part <prefix><kind>_<k> of the kind's class, coloured `c`.
  PlantPart& add_part(const std::string& kind, int k, TriMesh mesh, Color c) {
    PlantPart part;
    part.name = prefix + kind + "_" + std::to_string(k);
    part.kind = kind;
    part.class_id = spec.class_of(kind);
    part.mesh = std::move(mesh);
    set_rgba(&part, c);
    plant.parts.push_back(std::move(part));
    return plant.parts.back();
  }
};

constexpr Color kStemColor{0.30f, 0.48f, 0.18f};

// Trunk and the two stems of the V.
std::vector<Stem> add_stems(PlantBuild& b, const Vec3& base, double r_stem, double split_z, double v_azimuth) {
  Rng& rng = b.rng;
  const PlantParams& pp = b.spec.plant;
  const double H = b.plant.height_m;
  b.add_part("stem", 0,
             make_tube({base, base + Vec3(0, 0, split_z)}, {1.2 * r_stem, 1.1 * r_stem}, 6), kStemColor);
  std::vector<Stem> stems(2);
  for (int k = 0; k < 2; ++k) {
    const double az = v_azimuth + k * M_PI + rng.uniform(-20.0, 20.0) * kDeg;
    const double lean = rng.uniform(pp.v_angle_min_deg, pp.v_angle_max_deg) * kDeg;
    const Vec3 out(std::cos(az), std::sin(az), 0.0);
    const Vec3 side(-out.y(), out.x(), 0.0);
    const double wiggle_phase = rng.uniform(0.0, 2.0 * M_PI);
    const int segments = 8;
    for (int i = 0; i <= segments; ++i) {
      const double s = static_cast<double>(i) / segments;
      const double z = split_z + s * (H - split_z);
      const double wiggle = 0.015 * std::sin(wiggle_phase + 5.0 * s);
      stems[k].points.push_back(base + Vec3(0, 0, z) + (z - split_z) * std::tan(lean) * out + wiggle * side);
      stems[k].radii.push_back(r_stem * (1.0 - 0.45 * s));
    }
    b.add_part("stem", k + 1, make_tube(stems[k].points, stems[k].radii, 6), kStemColor);
  }
  return stems;
}

// Leaves: alternate (137.5 degree) along each stem, on petioles.
void add_leaves(PlantBuild& b, const std::vector<Stem>& stems, const Vec3& base) {
  Rng& rng = b.rng;
  const PlantParams& pp = b.spec.plant;
  const double H = b.plant.height_m;
  int leaf_count = 0;
  for (int k = 0; k < 2; ++k) {
    const int n = rng.integer(pp.leaves_per_stem_min, pp.leaves_per_stem_max);
    double azimuth = rng.uniform(0.0, 2.0 * M_PI);
    for (int i = 0; i < n; ++i) {
      const double z = base.z() + H * (0.25 + 0.72 * (i + rng.uniform(0.0, 0.8)) / std::max(n, 1));
      azimuth += 137.5 * kDeg + rng.uniform(-15.0, 15.0) * kDeg;
      const Vec3 node = stems[k].at_height(z);
      const Vec3 out(std::cos(azimuth), std::sin(azimuth), 0.0);
      const double lp = rng.uniform(pp.petiole_length_min_m, pp.petiole_length_max_m);
      const Vec3 tip = node + lp * (out + Vec3(0, 0, 0.5)).normalized();
      b.add_part("petiole", leaf_count,
                 make_tube({node, 0.5 * (node + tip) + Vec3(0, 0, 0.004), tip}, {0.0018, 0.0016, 0.0014}, 4),
                 kStemColor);
      const double L = rng.uniform(pp.leaf_length_min_m, pp.leaf_length_max_m);
      TriMesh blade = make_leaf(L, pp.leaf_width_ratio * L, rng.uniform(0.1, 0.35), rng.uniform(0.5, 3.0), 0.001);
      const double pitch = rng.uniform(-10.0, 35.0) * kDeg;  // positive: blade points down
      const double roll = rng.uniform(-20.0, 20.0) * kDeg;
      Pose T = Pose::Identity();
      T.translation() = tip;
      T.rotate(Eigen::AngleAxisd(azimuth, Vec3::UnitZ()));
      T.rotate(Eigen::AngleAxisd(pitch, Vec3::UnitY()));
      T.rotate(Eigen::AngleAxisd(roll, Vec3::UnitX()));
      blade.transform(T);
      b.add_part("leaf", leaf_count, std::move(blade), jitter(rng, {0.22f, 0.52f, 0.14f}, 0.04f));
      ++leaf_count;
    }
  }
}

// One attempt to hang fruit `f` from a peduncle: a fruit drawn at random, kept (true) unless
// it reaches the ground or overlaps a fruit `placed` before it.
bool try_hang_fruit(PlantBuild& b, const std::vector<Stem>& stems, const Vec3& base, int f,
                    std::vector<std::pair<Vec3, double>>* placed, int* next_instance) {
  Rng& rng = b.rng;
  const PlantParams& pp = b.spec.plant;
  const double H = b.plant.height_m;
  const bool blocky = rng.bernoulli(pp.blocky_fraction);
  const double width = blocky ? rng.uniform(pp.blocky_width_min_m, pp.blocky_width_max_m)
                              : rng.uniform(pp.conical_width_min_m, pp.conical_width_max_m);
  const double length = blocky ? rng.uniform(pp.blocky_length_min_m, pp.blocky_length_max_m)
                               : rng.uniform(pp.conical_length_min_m, pp.conical_length_max_m);
  const int k = rng.integer(0, 1);
  const double z = base.z() + H * rng.uniform(pp.fruit_zone_min, pp.fruit_zone_max);
  const double azimuth = rng.uniform(0.0, 2.0 * M_PI);
  const Vec3 node = stems[k].at_height(z);
  const Vec3 out(std::cos(azimuth), std::sin(azimuth), 0.0);
  const Vec3 top = node + (0.5 * width + 0.02) * out + Vec3(0, 0, -0.015);
  const Vec3 axis = (Vec3(0, 0, -1) + std::tan(rng.uniform(0.0, 15.0) * kDeg) *
                                          Vec3(std::cos(rng.uniform(0.0, 2 * M_PI)), std::sin(rng.uniform(0.0, 2 * M_PI)), 0))
                        .normalized();
  const Vec3 centre = top + 0.5 * length * axis;
  const double radius = 0.5 * std::max(width, length);
  if (top.z() - length < base.z() + 0.05) return false;
  bool clash = false;
  for (const auto& [c, r] : *placed) clash |= (c - centre).norm() < r + radius;
  if (clash) return false;
  placed->push_back({centre, radius});
  ++b.plant.fruits_placed;
  const std::string color = pick_color(rng, pp.fruit_colors);
  TriMesh mesh = make_lobed_revolution(fruit_profile(blocky, width, length), 14, blocky ? 4 : 3,
                                       blocky ? 0.10 : 0.06);
  Pose T = Pose::Identity();
  T.translation() = top;
  T.linear() = frame_with_z(-axis) * Eigen::AngleAxisd(rng.uniform(0.0, 2 * M_PI), Vec3::UnitZ()).toRotationMatrix();
  mesh.transform(T);
  b.add_part("peduncle", f, make_tube({node, top + Vec3(0, 0, 0.012)}, {0.003, 0.0035}, 5), {0.25f, 0.45f, 0.15f});
  PlantPart& fruit = b.add_part("fruit", f, std::move(mesh), jitter(rng, fruit_color(color), 0.03f));
  fruit.instance_id = (*next_instance)++;
  fruit.fruit_color = color;
  fruit.fruit_target = b.spec.is_ripe(color);
  if (!fruit.fruit_target) fruit.class_id = b.spec.class_of("unripe_fruit");
  fruit.fruit_shape = blocky ? "blocky" : "conical";
  return true;
}

// Fruits hanging from peduncles, not overlapping each other (60 attempts each).
void add_fruits(PlantBuild& b, const std::vector<Stem>& stems, const Vec3& base, int* next_instance) {
  const PlantParams& pp = b.spec.plant;
  const int n_fruits = b.rng.integer(pp.fruits_min, pp.fruits_max);
  b.plant.fruits_drawn = n_fruits;
  std::vector<std::pair<Vec3, double>> placed;  // bounding spheres
  for (int f = 0; f < n_fruits; ++f) {
    for (int attempt = 0; attempt < 60; ++attempt)
      if (try_hang_fruit(b, stems, base, f, &placed, next_instance)) break;
  }
}

// V-system support: each stem's string, from the fork straight up along the stem's lean to a
// wire 0.3 m above the stem's tip (the stem winds around it in a greenhouse). No random draws.
constexpr Color kTrellisColor{0.85f, 0.84f, 0.78f};
void add_trellis_strings(PlantBuild& b, const std::vector<Stem>& stems) {
  for (size_t k = 0; k < stems.size(); ++k) {
    const Vec3 fork = stems[k].points.front(), tip = stems[k].points.back();
    const Vec3 dir = (tip - fork).normalized();
    const Vec3 top = tip + (0.3 / std::max(dir.z(), 0.2)) * dir;
    b.add_part("trellis", static_cast<int>(k), make_tube({fork, top}, {0.001, 0.001}, 4), kTrellisColor);
  }
}

Plant make_plant(const WorldSpec& spec, int index, const Vec3& base, int* next_instance) {
  const PlantParams& pp = spec.plant;
  PlantBuild b{spec, Rng(mix_seed(spec.seed, static_cast<std::uint64_t>(index) + 1000)), Plant{},
               "p" + std::to_string(index) + "_"};
  b.plant.index = index;
  b.plant.base_position = base;
  b.plant.height_m = b.rng.uniform(pp.height_min_m, pp.height_max_m);
  const double r_stem = 0.5 * b.rng.uniform(pp.stem_diameter_min_m, pp.stem_diameter_max_m);
  const double split_z = b.rng.uniform(0.15, 0.25);
  const double v_azimuth = b.rng.uniform(0.0, 2.0 * M_PI);
  const std::vector<Stem> stems = add_stems(b, base, r_stem, split_z, v_azimuth);
  add_leaves(b, stems, base);
  add_fruits(b, stems, base, next_instance);
  if (pp.trellis_strings) add_trellis_strings(b, stems);
  return std::move(b.plant);
}

// An imported plant (its folder read once into `asset`) with its base at `base`, turned by
// `yaw_rad`; its fruits take the next instance ids and bring their folder's ground truth.
Plant place_imported(const WorldSpec& spec, const PlantAsset& asset, int index, const Vec3& base, double yaw_rad,
                     int* next_instance) {
  Plant plant;
  plant.index = index;
  plant.base_position = base;
  plant.height_m = asset.height_m;
  plant.import_dir = asset.dir;
  Pose T = Pose::Identity();
  T.translation() = base;
  T.rotate(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  const std::string prefix = "p" + std::to_string(index) + "_";
  std::map<int, int> instance_of_fruit;
  for (size_t k = 0; k < asset.parts.size(); ++k) {
    const ImportedPart& ip = asset.parts[k];
    PlantPart part;
    part.class_id = spec.classes.index_of(ip.class_name);
    if (part.class_id < 0)
      throw InputError(asset.dir + "/plant.yaml: class '" + ip.class_name + "' of material '" + ip.material +
                       "' is not in the world's class list (" + (spec.source_file.empty() ? "world" : spec.source_file) + ")");
    part.kind = ip.fruit >= 0 ? "fruit" : "imported";
    part.material = ip.material;
    part.name = prefix + (ip.fruit >= 0 ? "fruit_" + std::to_string(ip.fruit) : "part_" + std::to_string(k));
    std::copy(ip.rgba, ip.rgba + 4, part.rgba);
    part.mesh = ip.mesh;
    part.mesh.transform(T);
    if (ip.texture) {
      part.texture = ip.texture;
      part.texture_file = std::filesystem::absolute(asset.dir + "/" + ip.texture_file).lexically_normal().string();
      part.uv = ip.uv;
    }
    if (ip.fruit >= 0) {
      part.instance_id = (*next_instance)++;
      part.fruit_target = ip.target;
      const FruitTruth* truth = nullptr;
      for (const auto& f : asset.truth.fruits)
        if (f.instance_id == ip.fruit) truth = &f;
      CANOPY_CHECK(truth, "load_plant_asset checks every fruit part against fruits.json");
      part.fruit_color = truth->color;
      part.fruit_shape = truth->shape;
      part.has_truth_points = true;
      part.truth_area_m2 = truth->surface_area_m2;
      for (const auto& p : truth->surface_points) part.truth_points.push_back(T * p);
    }
    plant.parts.push_back(std::move(part));
  }
  return plant;
}

}  // namespace

size_t World::triangle_count() const {
  size_t n = 0;
  for (const auto& p : plants)
    if (!p.held) {
      n += p.triangles;
    } else {
      for (const auto& part : p.parts) n += part.mesh.faces.size();
    }
  return n;
}

bool World::plants_held() const {
  return std::all_of(plants.begin(), plants.end(), [](const Plant& p) { return p.held; });
}

std::shared_ptr<const Plant> World::plant(std::size_t i) const {
  CANOPY_CHECK(i < plants.size(), "plant index out of range");
  const Plant& p = plants[i];
  if (p.held) return std::shared_ptr<const Plant>(std::shared_ptr<const Plant>(), &p);  // the world's own, not owned
  CANOPY_CHECK(p.import_dir.empty(), "imported plants are always held");
  return std::make_shared<const Plant>(generate_plant(spec, p.index, p.base_position, p.first_instance));
}

Plant generate_plant(const WorldSpec& spec, int index, const Vec3& base, int first_instance) {
  int next_instance = first_instance;
  Plant plant = make_plant(spec, index, base, &next_instance);
  plant.first_instance = first_instance;
  for (const auto& part : plant.parts) plant.triangles += part.mesh.faces.size();
  return plant;
}

World generate_world(const WorldSpec& spec, const GenerateOptions& options) {
  spec.validate();
  World world;
  world.spec = spec;
  world.truth.point_spacing_m = spec.gt_point_spacing_m;
  int next_instance = 0;
  std::map<std::string, PlantAsset> assets;  // each plant folder read once
  auto asset = [&](const PlantPlacement& p) -> const PlantAsset& {
    auto it = assets.find(p.import_dir);
    if (it == assets.end()) it = assets.emplace(p.import_dir, load_plant_asset(p.import_dir)).first;
    return it->second;
  };
  // Each plant's ground truth is sampled as it is made (the same fruits in the same order as
  // sampling the whole world after); once the world holds options.drop_plants_from_triangles
  // triangles, the procedural plants' parts are dropped (World::plant() makes them again).
  double triangles = 0.0;
  bool dropping = false;
  const auto drop = [](Plant& p) {
    if (!p.import_dir.empty()) return;
    std::vector<PlantPart>().swap(p.parts);
    p.held = false;
  };
  const auto add = [&](Plant plant) {
    plant.triangles = 0;
    for (const auto& part : plant.parts) plant.triangles += part.mesh.faces.size();
    sample_plant_truth(spec, plant, &world.truth);
    triangles += static_cast<double>(plant.triangles);
    world.plants.push_back(std::move(plant));
    if (!dropping && triangles >= options.drop_plants_from_triangles) {
      dropping = true;
      for (Plant& p : world.plants) drop(p);
    } else if (dropping) {
      drop(world.plants.back());
    }
  };
  Rng layout(mix_seed(spec.seed, 1));
  for (int row = 0; row < spec.rows.rows; ++row) {
    const double y = row == 0 ? spec.rows.row_offset_m : -spec.rows.row_offset_m;
    for (int i = 0; i < spec.rows.plants_per_row; ++i) {
      const double j = spec.rows.position_jitter_m;
      const Vec3 base(spec.rows.x_start_m + i * spec.rows.plant_spacing_m + layout.uniform(-j, j),
                      y + layout.uniform(-j, j), 0.0);
      const int index = static_cast<int>(world.plants.size());
      const int first_instance = next_instance;
      // An imported plant in a slot stands exactly on it (the jitter is drawn all the same,
      // so the other plants do not move).
      Plant plant = [&] {
        if (const PlantPlacement* p = spec.placement_in_slot(row, i))
          return place_imported(spec, asset(*p), index, Vec3(spec.rows.x_start_m + i * spec.rows.plant_spacing_m, y, 0.0),
                                p->yaw_rad, &next_instance);
        return make_plant(spec, index, base, &next_instance);
      }();
      plant.first_instance = first_instance;
      add(std::move(plant));
    }
  }
  for (const auto& p : spec.placements)
    if (!p.in_slot) {
      const int first_instance = next_instance;
      Plant plant = place_imported(spec, asset(p), static_cast<int>(world.plants.size()),
                                   Vec3(p.position_m.x(), p.position_m.y(), 0.0), p.yaw_rad, &next_instance);
      plant.first_instance = first_instance;
      add(std::move(plant));
    }
  return world;
}

std::vector<std::string> unplaced_fruit_notes(const World& world) {
  std::vector<std::string> notes;
  for (const Plant& p : world.plants)
    if (p.fruits_placed < p.fruits_drawn)
      notes.push_back("plant " + std::to_string(p.index) + ": " + std::to_string(p.fruits_placed) + " of " +
                      std::to_string(p.fruits_drawn) + " fruits drawn fitted without overlapping (the others are left out)");
  return notes;
}

}  // namespace canopy::world
