// canopy world: generate a world's MJCF scene and its fruit ground truth.

#include <spdlog/spdlog.h>

#include <filesystem>

#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/read_file.h"
#include "canopy/sim/scene_mjcf.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_world_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string out;
    std::string config = settings::default_settings_path();
    std::string seg;
    bool strict = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("world", "Generate a world: MuJoCo scene (scene.xml) and fruit ground truth");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--seg", opt->seg,
                  "Labels the world will be mapped with: color (refuses imported plants whose target fruit colour "
                  "segmentation would not see) or truth (default: the config's)")
      ->check(CLI::IsMember({"color", "truth"}));
  sub->add_flag("--strict", opt->strict, kStrictColoursHelp);
  sub->callback([opt] {
    const world::WorldSpec spec = jobs::load_world_spec(opt->world);
    const world::World world = jobs::build_world(spec);
    settings::Settings settings = load_settings(opt->config);
    if (!opt->seg.empty()) settings.set("mapping.extractor.source", opt->seg, "--seg");
    jobs::check_world_colours(world, settings.mapping.extractor, opt->strict);
    const RobotConfig robot_config = default_robot_config();
    const robot::RobotDescription robot = robot::RobotDescription::load_urdf(robot_config.urdf_path);
    const sim::SceneDescription scene = sim::make_scene_mjcf(world, robot, robot_config);
    StagedDir out(opt->out, "world");
    write_file_atomic(out.path("scene.xml"), scene.mjcf);
    // The plant textures scene.xml names (file="textures/NAME"), so that it loads on its own.
    if (!scene.files.empty()) std::filesystem::create_directories(out.path("textures"));
    for (const auto& [name, disk_path] : scene.files) write_file_atomic(out.path("textures/" + name), read_file(disk_path));
    world.truth.save(out.path(""));
    nlohmann::json summary;
    summary["world"] = spec.name;
    summary["source"] = opt->world;
    summary["seed"] = spec.seed;
    summary["plants"] = world.plants.size();
    summary["fruits"] = world.truth.fruits.size();
    summary["fruit_surface_points"] = world.truth.total_points();
    summary["plant_triangles"] = world.triangle_count();
    summary["classes"] = spec.classes.names;
    summary["spec"] = spec.to_json();  // every resolved parameter: the world can be rebuilt from it
    nlohmann::json plants = nlohmann::json::array();
    for (std::size_t i = 0; i < world.plants.size(); ++i) {
      const std::shared_ptr<const world::Plant> plant = world.plant(i);  // generated again when not held
      const world::Plant& p = *plant;
      int fruits = 0;
      for (const auto& part : p.parts) fruits += part.instance_id != kNoInstance;
      plants.push_back({{"index", p.index},
                        {"base_position", {p.base_position.x(), p.base_position.y(), p.base_position.z()}},
                        {"height_m", p.height_m},
                        {"parts", p.parts.size()},
                        {"fruits", fruits},
                        {"import", p.import_dir}});  // "" for procedural plants
    }
    summary["plant_list"] = plants;
    write_json_atomic(out.path("world.json"), summary);
    out.commit();
    spdlog::info("wrote {}/scene.xml, fruits.json, fruit_points.csv, world.json ({} plants, {} fruits, {} triangles)",
                 opt->out, world.plants.size(), world.truth.fruits.size(), world.triangle_count());
  });
}

}  // namespace canopy::cli
