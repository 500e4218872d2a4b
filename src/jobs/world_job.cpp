#include "canopy/jobs/world_job.h"

#include <spdlog/spdlog.h>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/evaluation/segmentation_check.h"
#include "canopy/robot/robot_description.h"

namespace canopy::jobs {

world::WorldSpec load_world_spec(const std::string& path, const RobotConfig& robot, std::optional<std::uint64_t> seed) {
  world::WorldSpec spec = world::WorldSpec::load(find_data_file(path));
  if (seed) spec.seed = *seed;
  const robot::RobotDescription description = robot::RobotDescription::load_urdf(robot.urdf_path);
  const std::string base_link = description.joint(robot.base_joints.back()).child_link;
  spec.check_aisle(description.collision_half_width_m(base_link), robot.aisle_clearance_m);
  spdlog::info("world '{}' from {}: {} plants, seed {}", spec.name, path, spec.plant_count(), spec.seed);
  return spec;
}

world::World build_world(const world::WorldSpec& spec) {
  world::World w = world::generate_world(spec);
  for (const std::string& note : world::unplaced_fruit_notes(w)) spdlog::warn("world '{}': {}", spec.name, note);
  return w;
}

void check_world_colours(const world::World& world, const perception::ExtractorParams& extractor) {
  const bool colour = extractor.source == perception::LabelSource::kColor;
  for (const auto& m : evaluation::check_color_segmentation(world, extractor.color)) {
    const std::string what = m.plant + ": material '" + m.material + "'";
    if (m.problem.empty()) {
      spdlog::info("{} ({}{}): colour segmentation labels its {} {}", what, m.class_name, m.target ? "" : ", unripe",
                   m.textured ? "texture" : "colour", m.shares(world.spec.classes));
      continue;
    }
    const bool blind_target = m.class_name == world.spec.classes.target && m.target;
    if (colour && blind_target)
      throw InputError(what + ": " + m.problem + " (labels: color; give the plant fruit-coloured materials, or map with "
                       "--seg truth)");
    spdlog::warn("{}: {}", what, m.problem);
  }
}

world::World load_world(const WorldJobParams& params) {
  const world::WorldSpec spec = load_world_spec(params.world_file, params.robot, params.seed);
  world::World world = build_world(spec);
  check_world_colours(world, params.extractor);
  return world;
}

YAML::Node run_record(const std::string& command, const world::WorldSpec& spec) {
  YAML::Node n;
  n["command"] = command;
  n["world_file"] = spec.source_file;
  n["world"] = YAML::Load(spec.to_json().dump());  // JSON is YAML
  return n;
}

}  // namespace canopy::jobs
