#include "canopy/jobs/world_job.h"

#include <spdlog/spdlog.h>

#include <array>
#include <limits>
#include <map>
#include <vector>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/evaluation/segmentation_check.h"
#include "canopy/robot/robot_description.h"
#include "canopy/sim/scene_mjcf.h"

namespace canopy::jobs {

world::WorldSpec::BaseRange base_range(const RobotConfig& robot, const robot::RobotDescription& description) {
  if (robot.base_joints.size() < 2) throw InputError(robot.urdf_path + ": the robot names no planar base joints");
  const robot::Joint& x = description.joint(robot.base_joints[0]);
  const robot::Joint& y = description.joint(robot.base_joints[1]);
  const std::string base_link = description.joint(robot.base_joints.back()).child_link;
  world::WorldSpec::BaseRange r;
  const double inf = std::numeric_limits<double>::infinity();
  r.x_lower_m = x.limited() ? x.lower : -inf;
  r.x_upper_m = x.limited() ? x.upper : inf;
  r.y_lower_m = y.limited() ? y.lower : -inf;
  r.y_upper_m = y.limited() ? y.upper : inf;
  r.arm_x_m = description.relative_pose(base_link, robot.arm_base_frame, {}).translation().x();
  r.x_joint = x.name;
  r.y_joint = y.name;
  r.source = robot.urdf_path;
  return r;
}

world::WorldSpec load_world_spec(const std::string& path, const RobotConfig& robot, std::optional<std::uint64_t> seed) {
  world::WorldSpec spec = world::WorldSpec::load(find_data_file(path));
  if (seed) spec.seed = *seed;
  const robot::RobotDescription description = robot::RobotDescription::load_urdf(robot.urdf_path);
  const std::string base_link = description.joint(robot.base_joints.back()).child_link;
  spec.check_aisle(description.collision_half_width_m(base_link), robot.aisle_clearance_m);
  spec.check_base_range(base_range(robot, description));
  spdlog::info("world '{}' from {}: {} plants, seed {}", spec.name, path, spec.plant_count(), spec.seed);
  return spec;
}

world::World build_world(const world::WorldSpec& spec) {
  // A world too long for one rendered model (sim::SceneOptions::plant_window_min_triangles) is
  // rendered a window at a time: its plants are held only while a window, its truth voxels or
  // another consumer needs them (World::plant()). Smaller worlds are held whole, as always.
  world::GenerateOptions options;
  options.drop_plants_from_triangles = sim::SceneOptions{}.plant_window_min_triangles;
  world::World w = world::generate_world(spec, options);
  for (const std::string& note : world::unplaced_fruit_notes(w)) spdlog::warn("world '{}': {}", spec.name, note);
  return w;
}

std::vector<evaluation::FlatMaterial> robot_materials(const RobotConfig& robot, const world::WorldSpec& spec) {
  const robot::RobotDescription description = robot::RobotDescription::load_urdf(robot.urdf_path);
  // One material per distinct colour of the robot's visual shapes, named by the links wearing it.
  std::map<std::array<float, 3>, std::vector<std::string>> links_of;
  for (const auto& link : description.links())
    for (const auto& v : link.visuals) {
      auto& links = links_of[{v.rgba[0], v.rgba[1], v.rgba[2]}];
      if (links.empty() || links.back() != link.name) links.push_back(link.name);
    }
  std::vector<evaluation::FlatMaterial> out;
  for (const auto& [rgb, links] : links_of) {
    std::string name = fmt::format("colour {:.2f} {:.2f} {:.2f} of {}", rgb[0], rgb[1], rgb[2], links.front());
    if (links.size() > 1) name += fmt::format(" and {} more links", links.size() - 1);
    out.push_back(evaluation::FlatMaterial{"robot", name, spec.part_classes.robot, {rgb[0], rgb[1], rgb[2], 1.f}});
  }
  return out;
}

void check_world_colours(const world::World& world, const perception::ExtractorParams& extractor, bool strict,
                         const RobotConfig& robot) {
  const bool colour = extractor.source == perception::LabelSource::kColor;
  const SemanticClasses& classes = world.spec.classes;
  std::vector<evaluation::MaterialSegmentation> checked = evaluation::check_color_segmentation(world, extractor.color);
  for (auto& m : evaluation::check_color_segmentation(robot_materials(robot, world.spec), extractor.color, classes))
    checked.push_back(std::move(m));
  int fine = 0;
  for (const auto& m : checked) {
    const std::string what = m.owner + ": material '" + m.material + "'";
    const bool imported = m.owner != "ground" && m.owner != "robot" && m.owner != "procedural plants";
    if (m.problem.empty()) {
      ++fine;
      if (imported)
        spdlog::info("{} ({}{}): colour segmentation labels its {} {}", what, m.class_name, m.target ? "" : ", unripe",
                     m.textured ? "texture" : "colour", m.shares(classes));
      continue;
    }
    const bool blind_target = m.class_name == classes.target && m.target;
    if (colour && blind_target)
      throw InputError(what + ": " + m.problem + " (labels: color; give the plant fruit-coloured materials, or map with "
                       "--seg truth)");
    if (m.owner == "robot") {  // never mapped: the wrist camera drops the robot's own pixels (self-filter)
      spdlog::debug("{}: {} (harmless: the wrist camera's self-filter drops the robot's own pixels)", what, m.problem);
      ++fine;
      continue;
    }
    if (strict && colour) throw InputError(what + ": " + m.problem + " (labels: color; --strict)");
    spdlog::warn("{}: {}", what, m.problem);
  }
  spdlog::info("colour check of world '{}': {} of {} materials (ground, plants, robot) are labelled as their class",
               world.spec.name, fine, checked.size());
}

world::World load_world(const WorldJobParams& params) {
  const world::WorldSpec spec = load_world_spec(params.world_file, params.robot, params.seed);
  world::World world = build_world(spec);
  check_world_colours(world, params.extractor, params.strict_colours, params.robot);
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
