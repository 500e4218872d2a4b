// canopy import-plant: turn an existing plant model (any format assimp reads) into a plant
// folder that world files place next to procedural plants.

#include <spdlog/spdlog.h>

#include <map>

#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/evaluation/segmentation_check.h"
#include "canopy/world/plant_import.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_import_plant_command(CLI::App& app) {
  struct Options {
    std::string file, out, preset, up = "auto", gt = "surface", texture = "image";
    std::string config = settings::default_settings_path();
    bool strict = false;
    std::vector<std::string> classes;
    double unit_scale = 0.0;
    world::ImportOptions import;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "import-plant", "Import a plant model (COLLADA, OBJ, glTF, ...) as a plant folder that worlds can place");
  sub->add_option("file", opt->file, "Model file")->required();
  sub->add_option("--out", opt->out, "Plant folder to write (e.g. worlds/plants/NAME)")->required();
  sub->add_option("--class", opt->classes,
                  "Material mapping CLASS=REGEX (ripe fruit and other classes), CLASS:unripe=REGEX (fruit rendered "
                  "and labelled but not scored), default=CLASS (unmatched materials); first match wins, "
                  "case-insensitive, before the preset's rules");
  sub->add_option("--preset", opt->preset, "Mapping preset: capsicum (the community's Gazebo sweet-pepper models)");
  sub->add_option("--unit-scale", opt->unit_scale, "Metres per file unit (default: the file's own unit)");
  sub->add_option("--up", opt->up, "Up axis of the file: z, y or auto (glTF: y, others: z)")
      ->check(CLI::IsMember({"auto", "z", "y"}))
      ->capture_default_str();
  sub->add_option("--max-triangles", opt->import.max_triangles, "Triangle budget of the plant")->capture_default_str();
  sub->add_option("--gt", opt->gt, "Ground truth: surface (sampled by area) or vertices (the mesh's own)")
      ->check(CLI::IsMember({"surface", "vertices"}))
      ->capture_default_str();
  sub->add_option("--texture", opt->texture,
                  "Diffuse textures: image (rendered with them) or mean (each material's mean texel colour, weighted "
                  "by UV area, as its flat colour)")
      ->check(CLI::IsMember({"image", "mean"}))
      ->capture_default_str();
  sub->add_option("--config", opt->config, "Settings bundle whose colour segmentation (mapping.extractor.color) the "
                  "colour check uses")->capture_default_str();
  sub->add_flag("--strict", opt->strict,
                "Refuse the plant (exit 2, nothing written) when colour segmentation would not label a ripe-fruit "
                "material fruit, or would label much of another material fruit");
  sub->add_option("--spacing", opt->import.point_spacing_m, "Ground-truth point spacing [m] (surface)")->capture_default_str();
  sub->add_option("--min-fruit-size", opt->import.min_fruit_size_m,
                  "Fruit components with a smaller bounding-box diagonal [m] are fragments")->capture_default_str();
  sub->add_option("--merge-distance", opt->import.merge_distance_m,
                  "Fragments this close [m] to a fruit join it, farther ones are dropped")->capture_default_str();
  sub->add_option("--weld-tolerance", opt->import.weld_tolerance_m, "Vertices closer than this [m] are welded")
      ->capture_default_str();
  sub->add_option("--seed", opt->import.seed, "Seed of the ground-truth sampling")->capture_default_str();
  sub->callback([opt, sub] {
    world::ImportOptions o = opt->import;
    for (const auto& text : opt->classes) {
      world::ClassRule r = world::parse_class_rule(text);
      if (r.class_name == "default") {
        const world::ClassRule d = world::parse_class_rule(r.pattern + "=.*");
        if (o.fallback) throw InputError("--class '" + text + "': default given twice");
        o.fallback = d;
      } else {
        o.rules.push_back(r);
      }
    }
    if (!opt->preset.empty())
      for (const auto& r : world::class_preset(opt->preset)) o.rules.push_back(r);
    if (o.rules.empty() && !o.fallback) throw InputError("give --class CLASS=REGEX rules or --preset");
    if (sub->count("--unit-scale")) o.unit_scale = opt->unit_scale;
    o.up = opt->up;
    o.truth = opt->gt == "vertices" ? world::TruthMode::kVertices : world::TruthMode::kSurface;
    o.texture = opt->texture == "mean" ? world::TextureMode::kMean : world::TextureMode::kImage;
    StagedDir::check_writable(opt->out, "plant");
    const perception::ColorSegmentationParams bands = load_settings(opt->config).mapping.extractor.color;
    world::ImportedPlant plant = world::import_plant(opt->file, o);
    // The colour check: what the world's colour segmentation labels each material's colours.
    const SemanticClasses classes;  // background, leaf, fruit: the class list of worlds by default
    std::vector<std::string> problems;
    for (const auto& m : evaluation::check_color_segmentation(plant.parts, opt->file, bands, classes)) {
      for (auto& r : plant.report.materials)
        if (r.name == m.material) r.color_segmentation = m.shares(classes), r.color_problem = m.problem;
      if (!m.problem.empty()) problems.push_back("material '" + m.material + "': " + m.problem);
    }
    if (opt->strict && !problems.empty())
      throw InputError(opt->file + ": " + problems.front() + (problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) + " more)" : "") + " (--strict)");
    StagedDir out(opt->out, "plant");
    plant.save(out.path(""));
    out.commit();

    const world::ImportReport& r = plant.report;
    for (const auto& w : r.warnings) spdlog::warn("{}", w);
    for (const auto& m : r.materials) {
      std::string colour = m.colour;
      if (!m.texture_source.empty())
        colour += " (texture " + m.texture_source +
                  (m.texture_width > 0 ? ", " + std::to_string(m.texture_width) + " x " + std::to_string(m.texture_height) + " px" : "") + ")";
      spdlog::info("  material '{}' ({}{}, {} triangles): colour {}, mean rgb {:.2f} {:.2f} {:.2f}; colour segmentation: {}",
                   m.name, m.class_name, m.target ? "" : ", unripe", m.triangles, colour, m.rgba[0], m.rgba[1], m.rgba[2],
                   m.color_segmentation);
    }
    for (const auto& p : problems) spdlog::warn("COLOUR CHECK: {} (the plant is written; --strict refuses it)", p);
    spdlog::info("{}: {} ({}), unit {} m, scale {} m per unit, up {}", opt->file, r.format.empty() ? "?" : r.format,
                 plant.source_sha256.substr(0, 12), r.file_unit_m, r.unit_scale, r.up);
    spdlog::info("size {:.3f} x {:.3f} x {:.3f} m (height {:.3f} m, reach {:.3f} m from the base); {} triangles in, "
                 "{} degenerate dropped, {} points/lines dropped, {} exact duplicates",
                 r.size_m.x(), r.size_m.y(), r.size_m.z(), r.size_m.z(), r.radius_m, r.triangles_in,
                 r.degenerate_dropped, r.non_triangles_dropped, r.duplicate_triangles);
    std::map<std::string, long> per_class;
    for (const auto& p : plant.parts)
      per_class[p.class_name + (p.fruit >= 0 && !p.target ? " (unripe)" : "")] += static_cast<long>(p.mesh.faces.size());
    for (const auto& [name, n] : per_class) spdlog::info("  {}: {} triangles", name, n);
    for (const auto& f : plant.truth.fruits)
      spdlog::info("  fruit {} ({}{}): centre {:.3f} {:.3f} {:.3f} m, size {:.3f} m, {:.1f} cm2, {} ground-truth points",
                   f.instance_id, f.color, f.target ? "" : ", unripe", f.center.x(), f.center.y(), f.center.z(),
                   (f.bbox_max - f.bbox_min).maxCoeff(), f.surface_area_m2 * 1e4, f.surface_points.size());
    spdlog::info("wrote {} ({} parts, {} fruits, {} triangles)", opt->out, plant.parts.size(), plant.truth.fruits.size(),
                 plant.triangle_count());
  });
}

}  // namespace canopy::cli
