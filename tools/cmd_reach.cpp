// canopy reach: which camera views around the plants the arm can reach from one base pose:
// IK-reachable, collision-free and planned fractions (reach.json) and a map (reach.png). The
// work is jobs::reach (jobs/reach_job.h); this file translates the flags and prints.

#include <spdlog/spdlog.h>

#include <cstdio>

#include "canopy/common/value_text.h"
#include "canopy/jobs/reach_job.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_reach_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string config = settings::default_settings_path();
    std::string base, joints, out;
    motion::ReachParams grid;
    double voxel_m = 0.015;
    bool no_plan = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "reach", "Reachability of camera views around the plants from one base pose: reach.json, reach.png");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--base", opt->base, "Base pose x,y,yaw [m, m, rad]")->required();
  sub->add_option("--joints", opt->joints, "Start arm joints q1,...,q6 [rad] (default: home)");
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--radius", opt->grid.sphere.radius_m, "Camera distance to each fruit [m]")->capture_default_str();
  sub->add_option("--azimuths", opt->grid.sphere.azimuth_count, "Viewing azimuths per fruit")->capture_default_str();
  sub->add_option("--polar", opt->grid.sphere.polar_count, "Polar angles per fruit, 30..150 deg")->capture_default_str();
  sub->add_option("--max-target-distance", opt->grid.max_target_distance_m,
                  "Fruits farther from the arm base (horizontally) are skipped [m]")
      ->capture_default_str();
  sub->add_option("--voxel", opt->voxel_m, "Voxel size of the world's occupancy used for collisions [m]")
      ->capture_default_str();
  sub->add_flag("--no-plan", opt->no_plan, "IK and collisions only (no motion planning)");
  sub->callback([opt] {
    jobs::ReachJobParams p;
    p.world_file = opt->world;
    p.motion = load_settings(opt->config).motion;
    p.base = parse_base_pose(opt->base, "--base");
    if (!opt->joints.empty()) {
      const auto v = parse_numbers(opt->joints, kArmDof, "--joints");
      p.joints.emplace();
      std::copy(v.begin(), v.end(), p.joints->begin());
      p.joints_where = "--joints";
    }
    p.grid = opt->grid;
    p.grid.plan = !opt->no_plan;
    p.voxel_m = opt->voxel_m;
    p.out = opt->out;
    const jobs::ReachJobResult r = jobs::reach(p);
    if (!r.start_collision.empty())
      spdlog::warn("the start state is in collision at this base pose: {}", r.start_collision);
    const motion::ReachReport& report = r.report;
    std::printf("base %.3f,%.3f,%.3f: %d fruits, %zu views: IK-reachable %.3f, collision-free %.3f, planned %.3f, "
                "workspace filter kept %.3f (median planning %.1f ms)\n",
                p.base.x_m, p.base.y_m, p.base.yaw_rad, report.targets, report.samples.size(), report.fraction_ik(),
                report.fraction_collision_free(), report.fraction_planned(),
                report.samples.empty() ? 0.0 : double(report.count_workspace_kept()) / report.samples.size(),
                1e3 * report.median_planning_time_s());
    spdlog::info("wrote {}/reach.json and reach.png", opt->out);
  });
}

}  // namespace canopy::cli
