#include "canopy/world/ground_truth.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/common/csv.h"
#include "canopy/common/value_text.h"
#include "canopy/common/random.h"
#include "canopy/world/world.h"

namespace canopy::world {

size_t GroundTruth::total_points() const {
  size_t n = 0;
  for (const auto& f : fruits) n += f.surface_points.size();
  return n;
}

size_t GroundTruth::target_count() const {
  size_t n = 0;
  for (const auto& f : fruits) n += f.target ? 1 : 0;
  return n;
}

std::vector<const FruitTruth*> GroundTruth::fruits_of_plant(int plant_index) const {
  std::vector<const FruitTruth*> out;
  for (const auto& f : fruits)
    if (f.plant_index == plant_index) out.push_back(&f);
  return out;
}

std::vector<Vec3> sample_surface_points(const TriMesh& mesh, double spacing_m, std::uint64_t seed) {
  const double density = 1.0 / (spacing_m * spacing_m);  // points per m^2
  Rng rng(seed);
  std::vector<Vec3> points;
  for (const auto& tri : mesh.faces) {
    const Vec3& a = mesh.vertices[tri[0]];
    const Vec3& b = mesh.vertices[tri[1]];
    const Vec3& c = mesh.vertices[tri[2]];
    const double expected = 0.5 * (b - a).cross(c - a).norm() * density;
    // Stochastic rounding keeps the density exact on average over small triangles.
    const int n = static_cast<int>(expected) + (rng.uniform() < expected - std::floor(expected) ? 1 : 0);
    for (int i = 0; i < n; ++i) {
      const double s = std::sqrt(rng.uniform()), t = rng.uniform();
      points.push_back((1.0 - s) * a + s * (1.0 - t) * b + s * t * c);
    }
  }
  return points;
}

void sample_plant_truth(const WorldSpec& spec, const Plant& plant, GroundTruth* gt) {
  for (const auto& part : plant.parts) {
    if (part.instance_id == kNoInstance) continue;
    FruitTruth f;
    f.instance_id = part.instance_id;
    f.plant_index = plant.index;
    f.color = part.fruit_color;
    f.shape = part.fruit_shape;
    f.target = part.fruit_target;
    part.mesh.bounds(&f.bbox_min, &f.bbox_max);
    f.center = 0.5 * (f.bbox_min + f.bbox_max);
    f.surface_area_m2 = part.mesh.area();
    f.volume_m3 = std::abs(part.mesh.volume());
    // Imported plants bring their own ground truth (their folder's, placed in the world).
    f.surface_points = part.has_truth_points
                           ? part.truth_points
                           : sample_surface_points(part.mesh, spec.gt_point_spacing_m,
                                                   mix_seed(spec.seed, 1000000 + static_cast<std::uint64_t>(part.instance_id)));
    if (part.has_truth_points) f.surface_area_m2 = part.truth_area_m2;
    gt->fruits.push_back(std::move(f));
  }
}

GroundTruth sample_ground_truth(const World& world) {
  GroundTruth gt;
  gt.point_spacing_m = world.spec.gt_point_spacing_m;
  for (std::size_t i = 0; i < world.plants.size(); ++i) sample_plant_truth(world.spec, *world.plant(i), &gt);
  return gt;
}

namespace {
nlohmann::json vec_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 vec_from(const nlohmann::json& j) { return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()); }
}  // namespace

void GroundTruth::save(const std::string& dir) const {
  nlohmann::json j;
  j["point_spacing_m"] = point_spacing_m;
  j["fruits"] = nlohmann::json::array();
  for (const auto& f : fruits) {
    j["fruits"].push_back({{"instance_id", f.instance_id},
                           {"plant_index", f.plant_index},
                           {"color", f.color},
                           {"shape", f.shape},
                           {"target", f.target},
                           {"center", vec_json(f.center)},
                           {"bbox_min", vec_json(f.bbox_min)},
                           {"bbox_max", vec_json(f.bbox_max)},
                           {"surface_area_m2", f.surface_area_m2},
                           {"volume_m3", f.volume_m3},
                           {"num_points", f.surface_points.size()}});
  }
  write_json_atomic(dir + "/fruits.json", j);
  CsvWriter csv({"instance_id", "x", "y", "z"});
  for (const auto& f : fruits)
    for (const auto& p : f.surface_points)
      csv.add(f.instance_id).add(p.x(), NumberFormat::kDigits17).add(p.y(), NumberFormat::kDigits17)
          .add(p.z(), NumberFormat::kDigits17).end_row();
  write_file_atomic(dir + "/fruit_points.csv", csv.str());
}

GroundTruth GroundTruth::load(const std::string& dir) {
  GroundTruth gt;
  const std::string meta_path = dir + "/fruits.json";
  try {
    const nlohmann::json j = nlohmann::json::parse(read_file(meta_path));
    gt.point_spacing_m = j.at("point_spacing_m").get<double>();
    for (const auto& jf : j.at("fruits")) {
      FruitTruth f;
      f.instance_id = jf.at("instance_id").get<int>();
      f.plant_index = jf.at("plant_index").get<int>();
      f.color = jf.at("color").get<std::string>();
      f.shape = jf.at("shape").get<std::string>();
      f.target = jf.value("target", true);  // files written before the flag: every fruit is a target
      f.center = vec_from(jf.at("center"));
      f.bbox_min = vec_from(jf.at("bbox_min"));
      f.bbox_max = vec_from(jf.at("bbox_max"));
      f.surface_area_m2 = jf.at("surface_area_m2").get<double>();
      f.volume_m3 = jf.value("volume_m3", 0.0);  // files written before the volume: unknown
      gt.fruits.push_back(f);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(meta_path + ": malformed ground truth: " + e.what());
  }
  const std::string pts_path = dir + "/fruit_points.csv";
  std::istringstream in(read_file(pts_path));
  std::string line;
  std::getline(in, line);
  if (line != "instance_id,x,y,z") throw InputError(pts_path + ": missing header 'instance_id,x,y,z'");
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    const auto v = parse_numbers(line, 4, pts_path + ":" + std::to_string(line_no));
    const int id = static_cast<int>(v[0]);
    FruitTruth* target = nullptr;
    for (auto& f : gt.fruits)
      if (f.instance_id == id) target = &f;
    if (!target) throw InputError(pts_path + ":" + std::to_string(line_no) + ": unknown instance id " + std::to_string(id));
    target->surface_points.push_back(Vec3(v[1], v[2], v[3]));
  }
  return gt;
}

}  // namespace canopy::world
