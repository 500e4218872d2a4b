#include "canopy/evaluation/segmentation_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <unordered_map>

namespace canopy::evaluation {

namespace {

// One material's surface: its texture and texture coordinates, or its flat colour.
struct Surface {
  std::string material, class_name;
  bool target = true;
  const Image<Rgb8>* texture = nullptr;
  std::vector<world::FaceUv> uv;
  float rgba[4] = {0.f, 0.f, 0.f, 1.f};
  /// Several flat colours with their weights (procedural parts of one kind: one colour per
  /// part, weighted by its area); when set, used instead of rgba.
  std::vector<std::pair<Rgb8, double>> flat;
};

std::uint8_t to_byte(float x) { return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.f, 1.f) * 255.f)); }

MaterialSegmentation check(const Surface& s, const std::string& plant, const perception::ColorSegmentationParams& params,
                           const SemanticClasses& classes) {
  MaterialSegmentation m;
  m.owner = plant;
  m.material = s.material;
  m.class_name = s.class_name;
  m.target = s.target;
  m.textured = s.texture != nullptr;
  m.share.assign(static_cast<size_t>(classes.size()), 0.0);
  // Colours with their weights, labelled through segment_by_color itself (one pixel each).
  std::unordered_map<std::uint32_t, double> weight_of;
  if (s.texture) {
    const std::vector<double> w = world::texel_weights(s.texture->width, s.texture->height, s.uv);
    for (size_t i = 0; i < w.size(); ++i)
      if (w[i] > 0.0) {
        const Rgb8 c = s.texture->data[i];
        weight_of[(std::uint32_t(c.r) << 16) | (std::uint32_t(c.g) << 8) | c.b] += w[i];
      }
  }
  for (const auto& [c, w] : s.flat) weight_of[(std::uint32_t(c.r) << 16) | (std::uint32_t(c.g) << 8) | c.b] += w;
  if (weight_of.empty()) {
    const Rgb8 c{to_byte(s.rgba[0]), to_byte(s.rgba[1]), to_byte(s.rgba[2])};
    weight_of[(std::uint32_t(c.r) << 16) | (std::uint32_t(c.g) << 8) | c.b] = 1.0;
  }
  std::vector<std::pair<std::uint32_t, double>> colours(weight_of.begin(), weight_of.end());
  std::sort(colours.begin(), colours.end());  // a fixed order: the sums below do not depend on hashing
  Image<Rgb8> strip(static_cast<int>(colours.size()), 1);
  double total = 0.0;
  for (size_t i = 0; i < colours.size(); ++i) {
    const std::uint32_t k = colours[i].first;
    strip.data[i] = Rgb8{std::uint8_t(k >> 16), std::uint8_t((k >> 8) & 255), std::uint8_t(k & 255)};
    total += colours[i].second;
  }
  const Image<std::uint8_t> labels = perception::segment_by_color(strip, params, classes, "colour check of " + plant);
  for (size_t i = 0; i < colours.size(); ++i) m.share[labels.data[i]] += colours[i].second / total;

  const int target = classes.target_index();
  const double target_share = m.share[static_cast<size_t>(target)];
  char pct[32];
  std::snprintf(pct, sizeof pct, "%.0f%%", 100.0 * target_share);
  const std::string colours_of = m.textured ? "its texture" : s.flat.size() > 1 ? "its flat colours" : "its flat colour";
  if (s.class_name == classes.target && s.target && target_share < kMinTargetColourShare)
    m.problem = "target fruit material, but colour segmentation labels only " + std::string(pct) + " of " + colours_of +
                " '" + classes.target + "' (" + m.shares(classes) + "): its fruit will not be found";
  else if (s.class_name != classes.target && target_share > kMaxOtherTargetColourShare)
    m.problem = s.class_name + " material, but colour segmentation labels " + std::string(pct) + " of " + colours_of +
                " '" + classes.target + "' (" + m.shares(classes) + "): false fruit";
  return m;
}

std::vector<MaterialSegmentation> check_surfaces(const std::vector<Surface>& surfaces, const std::string& plant,
                                                 const perception::ColorSegmentationParams& params,
                                                 const SemanticClasses& classes) {
  std::vector<MaterialSegmentation> out;
  for (const auto& s : surfaces) out.push_back(check(s, plant, params, classes));
  return out;
}

// Adds a part to the surface of its material (first seen first).
void add(std::vector<Surface>* surfaces, const std::string& material, const std::string& class_name, bool target,
         const std::shared_ptr<const Image<Rgb8>>& texture, const std::vector<world::FaceUv>& uv, const float* rgba) {
  auto it = std::find_if(surfaces->begin(), surfaces->end(), [&](const Surface& s) { return s.material == material; });
  if (it == surfaces->end()) {
    surfaces->push_back(Surface{});
    it = surfaces->end() - 1;
    it->material = material;
    it->class_name = class_name;
    it->target = target;
    it->texture = texture.get();
    std::copy(rgba, rgba + 4, it->rgba);
  }
  if (texture) it->uv.insert(it->uv.end(), uv.begin(), uv.end());
}

}  // namespace

std::string MaterialSegmentation::shares(const SemanticClasses& classes) const {
  std::vector<std::pair<double, int>> order;
  for (size_t c = 0; c < share.size(); ++c) order.push_back({-share[c], static_cast<int>(c)});
  std::sort(order.begin(), order.end());
  std::string text;
  char b[64];
  for (const auto& [neg, c] : order) {
    if (-neg <= 0.0 && !text.empty()) continue;
    std::snprintf(b, sizeof b, "%s%s %.2f", text.empty() ? "" : ", ", classes.names[static_cast<size_t>(c)].c_str(), -neg);
    text += b;
  }
  return text;
}

std::vector<MaterialSegmentation> check_color_segmentation(const std::vector<world::ImportedPart>& parts,
                                                           const std::string& plant,
                                                           const perception::ColorSegmentationParams& params,
                                                           const SemanticClasses& classes) {
  std::vector<Surface> surfaces;
  for (const auto& p : parts) add(&surfaces, p.material, p.class_name, p.fruit < 0 || p.target, p.texture, p.uv, p.rgba);
  return check_surfaces(surfaces, plant, params, classes);
}

std::vector<MaterialSegmentation> check_color_segmentation(const std::vector<FlatMaterial>& materials,
                                                           const perception::ColorSegmentationParams& params,
                                                           const SemanticClasses& classes) {
  std::vector<MaterialSegmentation> out;
  for (const FlatMaterial& f : materials) {
    Surface s;
    s.material = f.material;
    s.class_name = f.class_name;
    std::copy(f.rgba, f.rgba + 4, s.rgba);
    out.push_back(check(s, f.owner, params, classes));
  }
  return out;
}

std::vector<FlatMaterial> ground_materials(const world::WorldSpec& spec) {
  const std::string ground = spec.part_classes.ground;
  const world::GroundLook& g = spec.ground;
  std::vector<FlatMaterial> out;
  out.push_back(FlatMaterial{"ground", "film", ground,
                             {float(g.film_r), float(g.film_g), float(g.film_b), 1.f}});
  if (g.path_width_m > 0.0)
    out.push_back(FlatMaterial{"ground", "path", ground, {float(g.path_r), float(g.path_g), float(g.path_b), 1.f}});
  if (g.heating_pipes)
    out.push_back(FlatMaterial{"ground", "heating pipes", ground, {float(g.pipe_r), float(g.pipe_g), float(g.pipe_b), 1.f}});
  return out;
}

std::vector<MaterialSegmentation> check_color_segmentation(const world::World& world,
                                                           const perception::ColorSegmentationParams& params) {
  const SemanticClasses& classes = world.spec.classes;
  std::vector<MaterialSegmentation> out = check_color_segmentation(ground_materials(world.spec), params, classes);
  // Procedural plants: one material per part kind (fruits: per colour), its colours weighted by
  // the parts' areas.
  std::map<std::string, Surface> procedural;
  for (std::size_t i = 0; i < world.plants.size(); ++i) {
    const std::shared_ptr<const world::Plant> plant = world.plant(i);  // a plant not held: generated again
    for (const auto& p : plant->parts) {
      if (!p.material.empty() || p.texture) continue;  // an imported plant's part
      const bool fruit = p.instance_id != kNoInstance;
      const std::string name = fruit ? p.kind + " (" + p.fruit_color + ")" : p.kind;
      Surface& s = procedural[name];
      s.material = name;
      s.class_name = classes.names[static_cast<size_t>(p.class_id)];
      s.target = !fruit || p.fruit_target;
      s.flat.push_back({Rgb8{to_byte(p.rgba[0]), to_byte(p.rgba[1]), to_byte(p.rgba[2])}, std::max(p.mesh.area(), 1e-12)});
    }
  }
  for (const auto& [name, s] : procedural) out.push_back(check(s, "procedural plants", params, classes));
  std::set<std::string> done;
  for (const auto& plant : world.plants) {  // imported plants: always held
    if (plant.import_dir.empty() || !done.insert(plant.import_dir).second) continue;
    std::vector<Surface> surfaces;
    for (const auto& p : plant.parts)
      add(&surfaces, p.material, classes.names[static_cast<size_t>(p.class_id)],
          p.instance_id == kNoInstance || p.fruit_target, p.texture, p.uv, p.rgba);
    for (auto& m : check_surfaces(surfaces, plant.import_dir, params, classes)) out.push_back(std::move(m));
  }
  return out;
}

}  // namespace canopy::evaluation
