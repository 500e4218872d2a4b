// The plant folder `canopy import-plant` writes and worlds read back: plant.yaml (source,
// scale, classes, parts, fruits), one OBJ per part, and the fruit ground truth.

#include <openssl/evp.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/world/plant_import.h"

namespace canopy::world {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPlantFile = "plant.yaml";

// A name usable as a file name.
std::string file_stem(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out.empty() ? std::string("part") : out;
}

std::string part_file(const ImportedPart& p, size_t index) {
  if (p.fruit >= 0) return "meshes/fruit_" + std::to_string(p.fruit) + ".obj";
  return "meshes/" + file_stem(p.class_name) + "_" + std::to_string(index) + "_" + file_stem(p.material) + ".obj";
}

std::string obj_text(const ImportedPart& p) {
  std::string s = "# canopy import-plant: material '" + p.material + "', class " + p.class_name + "\n";
  char line[128];
  for (const auto& v : p.mesh.vertices) {
    c_snprintf(line, sizeof(line), "v %.9g %.9g %.9g\n", v.x(), v.y(), v.z());
    s += line;
  }
  if (p.texture) {
    // One texture coordinate per face corner (OBJ's v = 0 is the image's bottom row).
    for (const auto& f : p.uv)
      for (const auto& t : f) {
        c_snprintf(line, sizeof(line), "vt %.9g %.9g\n", t.x(), t.y());
        s += line;
      }
    for (size_t k = 0; k < p.mesh.faces.size(); ++k) {
      const auto& f = p.mesh.faces[k];
      const size_t t = 3 * k + 1;
      c_snprintf(line, sizeof(line), "f %d/%zu %d/%zu %d/%zu\n", f[0] + 1, t, f[1] + 1, t + 1, f[2] + 1, t + 2);
      s += line;
    }
    return s;
  }
  for (const auto& f : p.mesh.faces) {
    c_snprintf(line, sizeof(line), "f %d %d %d\n", f[0] + 1, f[1] + 1, f[2] + 1);
    s += line;
  }
  return s;
}

}  // namespace

void ImportedPlant::save(const std::string& dir) const {
  fs::create_directories(dir + "/meshes");
  YAML::Emitter y;
  y << YAML::Comment("Written by canopy import-plant; worlds place it with plant: {import: <this folder>}");
  y << YAML::BeginMap;
  y << YAML::Key << "source" << YAML::Value << source_path;
  y << YAML::Key << "source_sha256" << YAML::Value << source_sha256;
  y << YAML::Key << "format" << YAML::Value << report.format;
  y << YAML::Key << "file_unit_m" << YAML::Value << report.file_unit_m;
  y << YAML::Key << "unit_scale" << YAML::Value << report.unit_scale;
  y << YAML::Key << "up" << YAML::Value << report.up;
  y << YAML::Key << "size_m" << YAML::Value << YAML::Flow << YAML::BeginSeq << report.size_m.x() << report.size_m.y()
    << report.size_m.z() << YAML::EndSeq;
  y << YAML::Key << "height_m" << YAML::Value << report.size_m.z();
  y << YAML::Key << "radius_m" << YAML::Value << report.radius_m;
  y << YAML::Key << "triangles" << YAML::Value << triangle_count();
  y << YAML::Key << "ground_truth" << YAML::Value << (options.truth == TruthMode::kVertices ? "vertices" : "surface");
  y << YAML::Key << "gt_point_spacing_m" << YAML::Value << options.point_spacing_m;
  y << YAML::Key << "report" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "triangles_in" << YAML::Value << report.triangles_in;
  y << YAML::Key << "degenerate_dropped" << YAML::Value << report.degenerate_dropped;
  y << YAML::Key << "non_triangles_dropped" << YAML::Value << report.non_triangles_dropped;
  y << YAML::Key << "duplicate_triangles" << YAML::Value << report.duplicate_triangles;
  y << YAML::Key << "fragments_merged" << YAML::Value << report.fragments_merged;
  y << YAML::Key << "fragments_dropped" << YAML::Value << report.fragments_dropped;
  y << YAML::Key << "simplify_cell_m" << YAML::Value << report.simplify_cell_m;
  y << YAML::EndMap;
  y << YAML::Key << "texture_mode" << YAML::Value << (options.texture == TextureMode::kMean ? "mean" : "image");
  // The class of every material and what became of its colour (one entry per material,
  // fruit instances folded in).
  y << YAML::Key << "materials" << YAML::Value << YAML::BeginMap;
  std::set<std::string> listed;
  for (const auto& p : parts)
    if (listed.insert(p.material).second) {
      y << YAML::Key << p.material << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "class" << YAML::Value
        << p.class_name << YAML::Key << "target" << YAML::Value << p.target;
      for (const auto& m : report.materials) {
        if (m.name != p.material) continue;
        y << YAML::Key << "colour" << YAML::Value << m.colour;
        if (!m.texture_source.empty())
          y << YAML::Key << "texture_source" << YAML::Value << m.texture_source << YAML::Key << "texture_px" << YAML::Value
            << YAML::Flow << YAML::BeginSeq << m.texture_width << m.texture_height << YAML::EndSeq;
        y << YAML::Key << (m.colour == "image" ? "mean_rgb" : "rgb") << YAML::Value << YAML::Flow << YAML::BeginSeq
          << m.rgba[0] << m.rgba[1] << m.rgba[2] << YAML::EndSeq;
        if (!m.color_segmentation.empty()) y << YAML::Key << "color_segmentation" << YAML::Value << m.color_segmentation;
        if (!m.color_problem.empty()) y << YAML::Key << "color_problem" << YAML::Value << m.color_problem;
        break;
      }
      y << YAML::EndMap;
    }
  y << YAML::EndMap;
  y << YAML::Key << "parts" << YAML::Value << YAML::BeginSeq;
  for (size_t i = 0; i < parts.size(); ++i) {
    const ImportedPart& p = parts[i];
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "file" << YAML::Value << part_file(p, i) << YAML::Key << "material"
      << YAML::Value << p.material << YAML::Key << "class" << YAML::Value << p.class_name;
    if (p.fruit >= 0) y << YAML::Key << "fruit" << YAML::Value << p.fruit << YAML::Key << "target" << YAML::Value << p.target;
    y << YAML::Key << "rgba" << YAML::Value << YAML::Flow << YAML::BeginSeq << p.rgba[0] << p.rgba[1] << p.rgba[2]
      << p.rgba[3] << YAML::EndSeq;
    if (p.texture) y << YAML::Key << "texture" << YAML::Value << p.texture_file;
    y << YAML::Key << "triangles" << YAML::Value << p.mesh.faces.size() << YAML::EndMap;
  }
  y << YAML::EndSeq;
  y << YAML::Key << "fruits" << YAML::Value << YAML::BeginSeq;
  for (const auto& f : truth.fruits)
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "fruit" << YAML::Value << f.instance_id << YAML::Key << "material"
      << YAML::Value << f.color << YAML::Key << "target" << YAML::Value << f.target << YAML::Key << "center"
      << YAML::Value << YAML::Flow << YAML::BeginSeq << f.center.x() << f.center.y() << f.center.z() << YAML::EndSeq
      << YAML::Key << "points" << YAML::Value << f.surface_points.size() << YAML::EndMap;
  y << YAML::EndSeq;
  y << YAML::EndMap;
  std::set<std::string> textures;
  for (const auto& p : parts)
    if (p.texture && textures.insert(p.texture_file).second) {
      fs::create_directories(dir + "/textures");
      write_png(dir + "/" + p.texture_file, *p.texture);
    }
  for (size_t i = 0; i < parts.size(); ++i) write_file_atomic(dir + "/" + part_file(parts[i], i), obj_text(parts[i]));
  truth.save(dir);
  write_file_atomic(dir + "/" + kPlantFile, std::string(y.c_str()) + "\n");
}

void read_plant_size(const std::string& dir, double* height_m, double* radius_m) {
  YamlReader y = YamlReader::load_file(dir + "/" + kPlantFile);
  *height_m = y.require<double>("height_m");
  *radius_m = y.require<double>("radius_m");
  y.check(std::isfinite(*height_m) && *height_m > 0.0, "height_m", "must be > 0");
  y.check(std::isfinite(*radius_m) && *radius_m >= 0.0, "radius_m", "must be >= 0");
}

PlantAsset load_plant_asset(const std::string& dir) {
  const std::string file = dir + "/" + kPlantFile;
  PlantAsset a;
  a.dir = dir;
  read_plant_size(dir, &a.height_m, &a.radius_m);
  a.truth = GroundTruth::load(dir);
  YamlReader y = YamlReader::load_file(file);
  YAML::Node parts;
  try {
    parts = y.require<YAML::Node>("parts");
  } catch (const InputError&) {
    throw InputError(file + ": missing key 'parts'");
  }
  if (!parts.IsSequence() || parts.size() == 0) throw InputError(file + ": key 'parts' must be a non-empty list");
  std::set<int> fruits;
  std::map<std::string, std::shared_ptr<const Image<Rgb8>>> textures;  // each file read once
  for (size_t i = 0; i < parts.size(); ++i) {
    YamlReader p(parts[i], file, "parts[" + std::to_string(i) + "]");
    ImportedPart part;
    const std::string mesh_file = p.require<std::string>("file");
    p.check(mesh_file.find("..") == std::string::npos && !fs::path(mesh_file).is_absolute(), "file",
            "must be a path inside the plant folder");
    part.material = p.require<std::string>("material");
    part.class_name = p.require<std::string>("class");
    part.fruit = p.get("fruit", -1);
    part.target = p.get("target", true);
    const auto rgba = p.require<std::vector<double>>("rgba");
    p.check(rgba.size() == 4, "rgba", "must be [r, g, b, a]");
    for (int k = 0; k < 4; ++k) {
      p.check(rgba[static_cast<size_t>(k)] >= 0.0 && rgba[static_cast<size_t>(k)] <= 1.0, "rgba", "must lie in [0, 1]");
      part.rgba[k] = static_cast<float>(rgba[static_cast<size_t>(k)]);
    }
    const long triangles = p.require<long>("triangles");
    part.texture_file = p.get("texture", std::string());
    p.check(part.texture_file.find("..") == std::string::npos && !fs::path(part.texture_file).is_absolute(), "texture",
            "must be a path inside the plant folder");
    p.finish();
    if (part.texture_file.empty()) {
      part.mesh = read_mesh_file(dir + "/" + mesh_file);
    } else {
      part.mesh = read_mesh_file(dir + "/" + mesh_file, &part.uv);
      auto it = textures.find(part.texture_file);
      if (it == textures.end())
        it = textures.emplace(part.texture_file, std::make_shared<const Image<Rgb8>>(read_png_rgb(dir + "/" + part.texture_file))).first;
      part.texture = it->second;
    }
    if (static_cast<long>(part.mesh.faces.size()) != triangles)
      throw InputError(dir + "/" + mesh_file + ": " + std::to_string(part.mesh.faces.size()) + " triangles, but " + file +
                       " says " + std::to_string(triangles));
    if (part.fruit >= 0) {
      const bool known = std::any_of(a.truth.fruits.begin(), a.truth.fruits.end(),
                                     [&](const FruitTruth& f) { return f.instance_id == part.fruit; });
      if (!known || !fruits.insert(part.fruit).second)
        throw InputError(file + ": key 'parts[" + std::to_string(i) + "].fruit': fruit " + std::to_string(part.fruit) +
                         " is unknown to fruits.json or listed twice");
    }
    a.parts.push_back(std::move(part));
  }
  if (fruits.size() != a.truth.fruits.size())
    throw InputError(file + ": fruits.json has " + std::to_string(a.truth.fruits.size()) + " fruits but parts name " +
                     std::to_string(fruits.size()));
  return a;
}

std::string file_sha256(const std::string& path) {
  const std::string bytes = read_file(path);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    throw InternalError("SHA-256 failed");
  std::string hex;
  char two[3];
  for (unsigned i = 0; i < length; ++i) {
    c_snprintf(two, sizeof(two), "%02x", digest[i]);
    hex += two;
  }
  return hex;
}

}  // namespace canopy::world
