// Plant import: the file's per-material triangle soups (plant_scene.cpp reads them through
// assimp) become a plant: units and the up axis converted, the base at the origin, welded,
// materials mapped to classes and colours, fruit split into instances with their ground
// truth, leaves and stems simplified to the triangle budget.

#include "canopy/world/plant_import.h"
#include "canopy/world/world_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <regex>
#include <set>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "plant_scene.h"

namespace canopy::world {

namespace fs = std::filesystem;

namespace {

// Vertex-clustering cells tried, in order, when the plant is over its triangle budget.
constexpr double kSimplifyCellsM[] = {0.001, 0.002, 0.004, 0.008, 0.016};

// ---- small helpers ------------------------------------------------------------------

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(static_cast<size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[static_cast<size_t>(a)] != a) a = parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
    return a;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);  // smallest id is the root: deterministic
  }
};

double box_gap(const Vec3& lo_a, const Vec3& hi_a, const Vec3& lo_b, const Vec3& hi_b) {
  const Vec3 gap = (lo_b - hi_a).cwiseMax(lo_a - hi_b).cwiseMax(Vec3::Zero());
  return gap.norm();
}

// Fallback flat colours (materials without a diffuse colour) per class.
void default_rgba(const std::string& class_name, bool target, float* rgba) {
  const float leaf[3] = {0.22f, 0.52f, 0.14f}, ripe[3] = {0.75f, 0.06f, 0.05f}, unripe[3] = {0.55f, 0.70f, 0.10f},
              other[3] = {0.5f, 0.5f, 0.5f};
  const float* c = class_name == "leaf" ? leaf : class_name == "fruit" ? (target ? ripe : unripe) : other;
  std::copy(c, c + 3, rgba);
  rgba[3] = 1.f;
}

struct CompiledRule {
  ClassRule rule;
  std::regex re;
};

std::string rule_text(const ClassRule& r) {
  return r.class_name + (r.target ? "" : ":unripe") + "=" + r.pattern;
}

// A name usable as a file name.
std::string texture_stem(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out.empty() ? std::string("material") : out;
}

}  // namespace

// ---- class mapping ----------------------------------------------------------------------

ClassRule parse_class_rule(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError("--class '" + text + "': expected CLASS=REGEX or CLASS:unripe=REGEX");
  ClassRule r;
  r.class_name = text.substr(0, eq);
  r.pattern = text.substr(eq + 1);
  const size_t colon = r.class_name.find(':');
  if (colon != std::string::npos) {
    const std::string flag = r.class_name.substr(colon + 1);
    if (flag != "unripe") throw InputError("--class '" + text + "': unknown flag ':" + flag + "' (only ':unripe')");
    r.target = false;
    r.class_name.resize(colon);
  }
  if (r.class_name.empty()) throw InputError("--class '" + text + "': empty class name");
  return r;
}

std::vector<ClassRule> class_preset(const std::string& name) {
  // docs/background/capsicum_models.md: *frt1*/*frt2* ripe fruit, *frt0* unripe fruit, *lef* leaves,
  // *brn* stems (stems count as leaf, as in procedural worlds).
  if (name == "capsicum")
    return {{"fruit", "frt[12]", true}, {"fruit", "frt0", false}, {"leaf", "lef", true}, {"leaf", "brn", true}};
  throw InputError("--preset '" + name + "': unknown preset (known: capsicum)");
}

// ---- import -----------------------------------------------------------------------------

long ImportedPlant::triangle_count() const {
  long n = 0;
  for (const auto& p : parts) n += static_cast<long>(p.mesh.faces.size());
  return n;
}

namespace {

// The options' plausible ranges: a scale that turns a plant into a city or a speck, or a
// negative distance, is a typo (and would give absurd meshes or no ground truth).
void check_options(const ImportOptions& opt) {
  auto in_range = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  auto num = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (opt.unit_scale && !in_range(*opt.unit_scale, kMinUnitScale, kMaxUnitScale))
    throw InputError("--unit-scale: value '" + num(*opt.unit_scale) + "' must be in [" + num(kMinUnitScale) + ", " +
                     num(kMaxUnitScale) + "] metres per file unit");
  if (opt.up != "auto" && opt.up != "z" && opt.up != "y")
    throw InputError("--up: value '" + opt.up + "' must be z or y");
  if (opt.max_triangles < 1 || opt.max_triangles > kMaxImportTriangles)
    throw InputError("--max-triangles: value '" + std::to_string(opt.max_triangles) + "' must be in [1, " +
                     std::to_string(kMaxImportTriangles) + "]");
  if (!in_range(opt.point_spacing_m, 0.0005, 0.1)) throw InputError("--spacing: value '" + num(opt.point_spacing_m) + "' must be in [0.0005, 0.1] m");
  if (!in_range(opt.weld_tolerance_m, 0.0, 0.01))
    throw InputError("--weld-tolerance: value '" + num(opt.weld_tolerance_m) + "' must be in [0, 0.01] m");
  if (!in_range(opt.min_fruit_size_m, 0.0, 1.0))
    throw InputError("--min-fruit-size: value '" + num(opt.min_fruit_size_m) + "' must be in [0, 1] m");
  if (!in_range(opt.merge_distance_m, 0.0, 1.0))
    throw InputError("--merge-distance: value '" + num(opt.merge_distance_m) + "' must be in [0, 1] m");
}

// Every vertex of the scaled plant must be finite and the plant of plant size: NaN in a file,
// or a vertex at 1e30, would reach the meshes, the ground truth and the MuJoCo scene.
void check_geometry(const std::string& path, const std::vector<MaterialSoup>& soups) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& s : soups)
    for (const auto& t : s.triangles)
      for (const auto& v : t) {
        if (!v.allFinite())
          throw InputError(path + ": material '" + s.name + "' has a vertex that is not a finite number (NaN or inf)");
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
  const double extent = (hi - lo).maxCoeff();
  if (extent > kMaxPlantSizeM) {
    std::ostringstream os;
    os << path << ": the plant would be " << extent << " m across (at most " << kMaxPlantSizeM
       << " m): check --unit-scale or the file's unit";
    throw InputError(os.str());
  }
}

// Stage 1: the rules' regexes, compiled (a rule that does not compile is named).
std::vector<CompiledRule> compile_rules(const std::vector<ClassRule>& all) {
  std::vector<CompiledRule> rules;
  for (const auto& r : all) {
    try {
      rules.push_back({r, std::regex(r.pattern, std::regex::ECMAScript | std::regex::icase)});
    } catch (const std::regex_error& e) {
      throw InputError("--class '" + rule_text(r) + "': the regex does not compile: " + e.what());
    }
  }
  return rules;
}

// Stage 2: file -> plant frame: the root's unit replaced by the scale in use, then Y-up -> Z-up.
Eigen::Matrix4d file_to_plant_frame(const ImportReport& rep) {
  Eigen::Matrix4d T_out_file = Eigen::Matrix4d::Identity();
  T_out_file.topLeftCorner<3, 3>() *= rep.unit_scale / rep.file_unit_m;
  if (rep.up == "y") {
    Eigen::Matrix4d R = Eigen::Matrix4d::Zero();  // +90 degrees about x, exactly: y -> z, z -> -y
    R(0, 0) = R(3, 3) = 1.0, R(1, 2) = -1.0, R(2, 1) = 1.0;
    T_out_file = R * T_out_file;
  }
  return T_out_file;
}

// Stage 3's warning about triangles that exactly repeat others.
void warn_duplicates(ImportReport* rep) {
  if (rep->duplicate_triangles > 0) {
    std::string nodes;
    for (size_t i = 0; i < rep->duplicate_nodes.size() && i < 3; ++i) nodes += (i ? "; " : "") + rep->duplicate_nodes[i];
    rep->warnings.push_back(std::to_string(rep->duplicate_triangles) +
                            " triangles exactly repeat others (the same geometry instanced twice at the same place: " +
                            nodes + "); kept as the file says, counted once in the ground truth");
  }
}

// Stage 4: base at the origin: lowest point at z = 0, x and y at the centre of the lowest
// slice (the stem where it leaves the ground, not the centre of the canopy).
void move_base_to_origin(std::vector<MaterialSoup>* soups) {
  double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
  for (const auto& s : *soups)
    for (const auto& t : s.triangles)
      for (const auto& v : t) z_lo = std::min(z_lo, v.z()), z_hi = std::max(z_hi, v.z());
  const double slice = z_lo + std::max(0.01, 0.02 * (z_hi - z_lo));
  Vec2 xy_lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()), xy_hi = -xy_lo;
  for (const auto& s : *soups)
    for (const auto& t : s.triangles)
      for (const auto& v : t)
        if (v.z() <= slice) xy_lo = xy_lo.cwiseMin(v.head<2>()), xy_hi = xy_hi.cwiseMax(v.head<2>());
  const Vec2 xy = 0.5 * (xy_lo + xy_hi);
  const Vec3 base(xy.x(), xy.y(), z_lo);
  for (auto& s : *soups)
    for (auto& t : s.triangles)
      for (auto& v : t) v -= base;
}

// Stage 5: the class of every material with triangles: the first matching rule, else the
// fallback; unmatched materials, or no material of the fruit class, are an error.
std::vector<std::optional<ClassRule>> classify_materials(const std::string& path, const std::vector<MaterialSoup>& soups,
                                                         const std::vector<CompiledRule>& rules,
                                                         const ImportOptions& opt) {
  std::vector<std::string> unmatched, fruit_materials;
  std::vector<std::optional<ClassRule>> class_of(soups.size());
  for (size_t i = 0; i < soups.size(); ++i) {
    if (soups[i].triangles.empty()) continue;
    for (const auto& r : rules)
      if (std::regex_search(soups[i].name, r.re)) {
        class_of[i] = r.rule;
        break;
      }
    if (!class_of[i]) class_of[i] = opt.fallback;
    if (!class_of[i]) unmatched.push_back(soups[i].name);
    else if (class_of[i]->class_name == opt.fruit_class) fruit_materials.push_back(soups[i].name);
  }
  if (!unmatched.empty()) {
    std::string list;
    for (const auto& n : unmatched) list += (list.empty() ? "'" : ", '") + n + "'";
    throw InputError(path + ": no --class rule matches the material(s) " + list + " (add a rule or --class default=CLASS)");
  }
  if (fruit_materials.empty()) {
    std::string list;
    for (const auto& s : soups)
      if (!s.triangles.empty()) list += (list.empty() ? "'" : ", '") + s.name + "'";
    throw InputError(path + ": no material maps to the fruit class '" + opt.fruit_class + "' (materials: " + list + ")");
  }
  return class_of;
}

// How a material is drawn: its texture, or a flat colour.
struct Look {
  std::shared_ptr<const Image<Rgb8>> texture;  // rendered with it (TextureMode::kImage)
  std::string file;                            // its PNG in the plant folder
  float rgba[4] = {0.5f, 0.5f, 0.5f, 1.f};
};

// Stage 6 for a textured material (number `i`): its texture as an image, or its UV-area-
// weighted mean colour, or (no texture coordinates) its plain mean; a missing file keeps the
// flat colour already in `look`.
void texture_look(const PlantScene& scene, size_t i, const MaterialSoup& s, const ImportOptions& opt, Look* look,
                  MaterialReport* mr, ImportReport* rep) {
  std::optional<Image<Rgb8>> image = scene.load_texture(s.texture_ref);
  if (!image) {
    mr->colour = "missing";
    rep->warnings.push_back("material '" + s.name + "': its texture '" + s.texture_ref +
                            "' is not found beside the model; rendered in its flat " +
                            (s.has_color ? "diffuse colour" : "class colour"));
    return;
  }
  mr->texture_width = image->width;
  mr->texture_height = image->height;
  const bool has_uv = s.without_uv == 0;
  std::vector<double> weights;
  if (has_uv) weights = texel_weights(image->width, image->height, s.uv);
  const std::array<float, 3> mean = mean_color(*image, weights);
  std::copy(mean.begin(), mean.end(), look->rgba);
  look->rgba[3] = 1.f;
  if (!has_uv) {
    mr->colour = "no-uv";
    rep->warnings.push_back("material '" + s.name + "': " + std::to_string(s.without_uv) +
                            " of its triangles have no texture coordinates; rendered in the plain mean colour of "
                            "its texture '" + s.texture_ref + "'");
  } else if (opt.texture == TextureMode::kMean) {
    mr->colour = "mean";
  } else {
    mr->colour = "image";
    look->texture = std::make_shared<const Image<Rgb8>>(std::move(*image));
    look->file = "textures/" + std::to_string(i) + "_" + texture_stem(s.name) + ".png";
  }
}

// Stage 6: colour of every material: its texture (as an image or its UV-area-weighted mean),
// else its diffuse colour, else its class colour; each reported in `rep`.
std::vector<Look> material_looks(const PlantScene& scene, const std::vector<MaterialSoup>& soups,
                                 const std::vector<std::optional<ClassRule>>& class_of, const ImportOptions& opt,
                                 ImportReport* rep) {
  std::vector<Look> looks(soups.size());
  for (size_t i = 0; i < soups.size(); ++i) {
    if (!class_of[i]) continue;
    const MaterialSoup& s = soups[i];
    const ClassRule& cls = *class_of[i];
    Look& look = looks[i];
    MaterialReport mr;
    mr.name = s.name;
    mr.class_name = cls.class_name;
    mr.target = cls.target;
    mr.triangles = static_cast<long>(s.triangles.size());
    mr.texture_source = s.texture_ref;
    if (s.has_color) std::copy(s.rgba, s.rgba + 4, look.rgba);
    else default_rgba(cls.class_name, cls.target, look.rgba);
    if (s.has_texture) texture_look(scene, i, s, opt, &look, &mr, rep);
    std::copy(look.rgba, look.rgba + 4, mr.rgba);
    rep->materials.push_back(std::move(mr));
  }
  return looks;
}

// Gives a part its material's look: the texture (white under it), or the flat colour and no
// texture coordinates.
void paint(const Look& look, ImportedPart* part) {
  if (look.texture) {
    part->texture = look.texture;
    part->texture_file = look.file;
    std::fill(part->rgba, part->rgba + 4, 1.f);  // the texture replaces the diffuse colour
  } else {
    std::copy(look.rgba, look.rgba + 4, part->rgba);
    part->uv.clear();
  }
}

// A connected component of a fruit material's welded triangles.
struct Component {
  size_t material;
  TriMesh mesh;
  std::vector<bool> duplicate;
  std::vector<FaceUv> uv;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  bool fragment = false;
};

// Splits one fruit material's welded mesh (number `material`) into connected components,
// appended to `fruits` with their faces' duplicate flags and texture coordinates.
void add_components(size_t material, const TriMesh& mesh, const std::vector<bool>& dup, const std::vector<FaceUv>& uv,
                    std::vector<Component>* fruits) {
  UnionFind uf(static_cast<int>(mesh.vertices.size()));
  for (const auto& f : mesh.faces) uf.unite(f[0], f[1]), uf.unite(f[1], f[2]);
  std::map<int, size_t> comp_of_root;  // root vertex -> index in `fruits`
  for (size_t t = 0; t < mesh.faces.size(); ++t) {
    const int root = uf.find(mesh.faces[t][0]);
    auto [it, fresh] = comp_of_root.try_emplace(root, fruits->size());
    if (fresh) {
      fruits->push_back(Component{material, {}, {}, {}, Vec3::Zero(), Vec3::Zero(), false});
      fruits->back().mesh.vertices = mesh.vertices;  // compacted below
    }
    Component& c = (*fruits)[it->second];
    c.mesh.faces.push_back(mesh.faces[t]);
    c.duplicate.push_back(dup[t]);
    c.uv.push_back(uv[t]);
  }
}

// Stage 7: parts: one per material, welded; fruit materials are returned split into
// connected components (compacted, bounded, fragments marked) instead.
std::vector<Component> material_parts(std::vector<MaterialSoup>& soups,
                                      const std::vector<std::optional<ClassRule>>& class_of,
                                      const std::vector<Look>& looks, const ImportOptions& opt, ImportedPlant* plant) {
  std::vector<Component> fruits;
  for (size_t i = 0; i < soups.size(); ++i) {
    if (!class_of[i]) continue;
    MaterialSoup& s = soups[i];
    const ClassRule& cls = *class_of[i];
    long dropped = 0;
    std::vector<size_t> kept;
    TriMesh mesh = weld_triangles(s.triangles, opt.weld_tolerance_m, &dropped, &kept);
    std::vector<bool> dup;
    std::vector<FaceUv> uv;
    for (size_t k : kept) dup.push_back(s.duplicate[k]), uv.push_back(s.uv[k]);
    plant->report.degenerate_dropped += dropped;
    if (mesh.faces.empty()) continue;
    if (cls.class_name == opt.fruit_class) {
      add_components(i, mesh, dup, uv, &fruits);
      continue;
    }
    ImportedPart part;
    part.material = s.name;
    part.class_name = cls.class_name;
    part.target = cls.target;
    part.mesh = std::move(mesh);
    part.uv = std::move(uv);
    paint(looks[i], &part);
    plant->parts.push_back(std::move(part));
  }
  for (auto& c : fruits) {
    c.mesh = compact(c.mesh);
    c.mesh.bounds(&c.lo, &c.hi);
    c.fragment = (c.hi - c.lo).norm() < opt.min_fruit_size_m;
  }
  return fruits;
}

// Stage 7, fruits: fragments join the nearest whole fruit of the same ripeness within
// merge_distance_m (others are dropped); the whole fruits numbered by material name, then in
// the file's order.
std::vector<Component> whole_fruits(const std::string& path, const std::vector<Component>& fruits,
                                    const std::vector<MaterialSoup>& soups,
                                    const std::vector<std::optional<ClassRule>>& class_of, const ImportOptions& opt,
                                    ImportReport* rep) {
  std::vector<Component> whole;
  for (auto& c : fruits)
    if (!c.fragment) whole.push_back(c);
  for (const auto& c : fruits) {
    if (!c.fragment) continue;
    int best = -1;
    double best_gap = opt.merge_distance_m;
    for (size_t w = 0; w < whole.size(); ++w) {
      if (class_of[whole[w].material]->target != class_of[c.material]->target) continue;
      const double gap = box_gap(c.lo, c.hi, whole[w].lo, whole[w].hi);
      if (gap <= best_gap) best_gap = gap, best = static_cast<int>(w);
    }
    if (best < 0) {
      ++rep->fragments_dropped;
      continue;
    }
    Component& into = whole[static_cast<size_t>(best)];
    into.mesh.append(c.mesh);
    into.duplicate.insert(into.duplicate.end(), c.duplicate.begin(), c.duplicate.end());
    into.uv.insert(into.uv.end(), c.uv.begin(), c.uv.end());
    ++rep->fragments_merged;
  }
  if (rep->fragments_dropped + rep->fragments_merged > 0)
    rep->warnings.push_back(std::to_string(rep->fragments_merged) + " fruit fragment(s) smaller than " +
                            std::to_string(opt.min_fruit_size_m) + " m merged into their nearest fruit, " +
                            std::to_string(rep->fragments_dropped) + " dropped (no fruit within " +
                            std::to_string(opt.merge_distance_m) + " m)");
  std::stable_sort(whole.begin(), whole.end(),
                   [&](const Component& a, const Component& b) { return soups[a.material].name < soups[b.material].name; });
  if (whole.empty()) throw InputError(path + ": the fruit materials hold no fruit larger than " +
                                      std::to_string(opt.min_fruit_size_m) + " m");
  return whole;
}

// Stage 8: ground truth of fruit `k`, from its unique triangles (exact duplicates counted once).
FruitTruth fruit_truth(const Component& c, size_t k, const MaterialSoup& s, const ClassRule& cls,
                       const ImportOptions& opt) {
  TriMesh unique = c.mesh;
  unique.faces.clear();
  for (size_t t = 0; t < c.mesh.faces.size(); ++t)
    if (!c.duplicate[t]) unique.faces.push_back(c.mesh.faces[t]);
  unique = compact(unique);
  FruitTruth f;
  f.instance_id = static_cast<int>(k);
  f.plant_index = 0;
  f.color = s.name;
  f.shape = "imported";
  f.target = cls.target;
  unique.bounds(&f.bbox_min, &f.bbox_max);
  f.center = 0.5 * (f.bbox_min + f.bbox_max);
  f.surface_area_m2 = unique.area();
  f.volume_m3 = std::abs(unique.volume());
  f.surface_points = opt.truth == TruthMode::kVertices
                         ? unique.vertices
                         : sample_surface_points(unique, opt.point_spacing_m, mix_seed(opt.seed, 1000000 + k));
  return f;
}

// Stage 8: every whole fruit becomes a part of its own and a fruit of the ground truth.
void add_fruit_parts(std::vector<Component>& whole, const std::vector<MaterialSoup>& soups,
                const std::vector<std::optional<ClassRule>>& class_of, const std::vector<Look>& looks,
                const ImportOptions& opt, ImportedPlant* plant) {
  plant->truth.point_spacing_m = opt.point_spacing_m;
  for (size_t k = 0; k < whole.size(); ++k) {
    Component& c = whole[k];
    const MaterialSoup& s = soups[c.material];
    const ClassRule& cls = *class_of[c.material];
    plant->truth.fruits.push_back(fruit_truth(c, k, s, cls, opt));
    ImportedPart part;
    part.material = s.name;
    part.class_name = cls.class_name;
    part.target = cls.target;
    part.fruit = static_cast<int>(k);
    part.mesh = std::move(c.mesh);
    part.uv = std::move(c.uv);
    paint(looks[c.material], &part);
    plant->parts.push_back(std::move(part));
  }
}

// Stage 9, the budget: leaves and stems are simplified by vertex clustering with growing
// cells; fruit geometry is kept as it is (its ground truth and instances come from it).
void simplify_to_budget(const std::string& path, const ImportOptions& opt, ImportedPlant* plant) {
  ImportReport& rep = plant->report;
  if (plant->triangle_count() <= opt.max_triangles) return;
  const std::vector<ImportedPart> original = plant->parts;
  for (double cell : kSimplifyCellsM) {
    for (size_t p = 0; p < plant->parts.size(); ++p) {
      if (plant->parts[p].fruit >= 0) continue;
      std::vector<size_t> kept;
      plant->parts[p].mesh = cluster_vertices(original[p].mesh, cell, &kept);
      if (!original[p].uv.empty()) {
        plant->parts[p].uv.clear();
        for (size_t k : kept) plant->parts[p].uv.push_back(original[p].uv[k]);
      }
    }
    rep.simplify_cell_m = cell;
    if (plant->triangle_count() <= opt.max_triangles) break;
  }
  if (plant->triangle_count() > opt.max_triangles) {
    long fruit_tris = 0;
    for (const auto& p : plant->parts) fruit_tris += p.fruit >= 0 ? static_cast<long>(p.mesh.faces.size()) : 0;
    throw InputError(path + ": " + std::to_string(plant->triangle_count()) + " triangles (" +
                     std::to_string(fruit_tris) + " of them fruit, never simplified) after simplifying leaves and stems with " +
                     std::to_string(rep.simplify_cell_m * 1000) + " mm cells; --max-triangles is " +
                     std::to_string(opt.max_triangles));
  }
  plant->parts.erase(std::remove_if(plant->parts.begin(), plant->parts.end(),
                                    [](const ImportedPart& p) { return p.mesh.faces.empty(); }),
                     plant->parts.end());
  rep.warnings.push_back("simplified leaves and stems with " + std::to_string(rep.simplify_cell_m * 1000) +
                         " mm cells to meet --max-triangles " + std::to_string(opt.max_triangles));
}

// The plant's bounding-box size and radius (largest horizontal distance from the base).
void measure(ImportedPlant* plant) {
  ImportReport& rep = plant->report;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : plant->parts) {
    Vec3 a, b;
    p.mesh.bounds(&a, &b);
    lo = lo.cwiseMin(a), hi = hi.cwiseMax(b);
    for (const auto& v : p.mesh.vertices) rep.radius_m = std::max(rep.radius_m, v.head<2>().norm());
  }
  rep.size_m = hi - lo;
}

}  // namespace

ImportedPlant import_plant(const std::string& path, const ImportOptions& opt) {
  check_options(opt);
  const std::vector<CompiledRule> rules = compile_rules(opt.rules);

  ImportedPlant plant;
  plant.source_path = fs::absolute(path).string();
  plant.options = opt;
  ImportReport& rep = plant.report;
  const PlantScene scene(path);
  plant.source_sha256 = file_sha256(path);
  rep.format = scene.format();
  rep.file_unit_m = scene.file_unit_m();
  rep.unit_scale = opt.unit_scale ? *opt.unit_scale : rep.file_unit_m;
  rep.up = opt.up != "auto" ? opt.up : scene.default_up();

  std::vector<MaterialSoup> soups = scene.triangles_by_material(file_to_plant_frame(rep), &rep);
  if (rep.triangles_in == 0) throw InputError(path + ": the file holds no triangles");
  check_geometry(path, soups);
  warn_duplicates(&rep);
  move_base_to_origin(&soups);

  const std::vector<std::optional<ClassRule>> class_of = classify_materials(path, soups, rules, opt);
  const std::vector<Look> looks = material_looks(scene, soups, class_of, opt, &rep);
  const std::vector<Component> fruits = material_parts(soups, class_of, looks, opt, &plant);
  std::vector<Component> whole = whole_fruits(path, fruits, soups, class_of, opt, &rep);
  add_fruit_parts(whole, soups, class_of, looks, opt, &plant);
  simplify_to_budget(path, opt, &plant);
  measure(&plant);
  return plant;
}

TriMesh read_mesh_file(const std::string& path, std::vector<FaceUv>* uv) {
  const PlantScene scene(path);
  ImportReport rep;
  const std::vector<MaterialSoup> soups = scene.triangles_by_material(Eigen::Matrix4d::Identity(), &rep);
  std::vector<std::array<Vec3, 3>> all;
  std::vector<FaceUv> all_uv;
  long without_uv = 0;
  for (const auto& s : soups) {
    all.insert(all.end(), s.triangles.begin(), s.triangles.end());
    all_uv.insert(all_uv.end(), s.uv.begin(), s.uv.end());
    without_uv += s.without_uv;
  }
  if (uv && without_uv > 0)
    throw InputError(path + ": " + std::to_string(without_uv) + " triangles have no texture coordinates");
  long degenerate = 0;
  std::vector<size_t> kept;
  TriMesh mesh = weld_triangles(all, 0.0, &degenerate, &kept);
  if (uv) {
    uv->clear();
    for (size_t k : kept) uv->push_back(all_uv[k]);
  }
  return mesh;
}

}  // namespace canopy::world
