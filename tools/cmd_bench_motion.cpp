// canopy bench motion: IK time per solve, collision (validity) check time per state against
// the default world's occupancy, and planning success rate and times over random reachable
// goals (issue targets: IK <= 2 us, >= 95% success within 1 s each). The measuring is
// jobs::bench_motion (jobs/bench_motion.h); this file translates the flags and prints.

#include <spdlog/spdlog.h>

#include <cstdio>

#include "canopy/common/atomic_file.h"
#include "canopy/common/value_text.h"
#include "canopy/jobs/bench_motion.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_bench_motion(CLI::App& bench) {
  struct Options {
    std::string world = default_world_path();
    std::string config = settings::default_settings_path();
    std::string base = "0.75,0,0";
    std::string json;
    int ik_poses = 100000;
    int states = 20000;
    int goals = 100;
    std::uint64_t seed = 7;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand("motion", "IK us/solve, validity check us/state, planning success and times");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--base", opt->base, "Base pose x,y,yaw for the collision and planning parts")->capture_default_str();
  sub->add_option("--ik-poses", opt->ik_poses, "Random poses for the IK timing")->capture_default_str()->check(CLI::Range(100, 10000000));
  sub->add_option("--states", opt->states, "Random states for the validity timing")->capture_default_str()->check(CLI::Range(100, 10000000));
  sub->add_option("--goals", opt->goals, "Random reachable goals to plan to")->capture_default_str()->check(CLI::Range(1, 100000));
  sub->add_option("--seed", opt->seed, "Seed of the random poses and goals")->capture_default_str();
  sub->add_option("--json", opt->json, "Also write the figures to this JSON file");
  sub->callback([opt] {
    jobs::BenchMotionParams p;
    p.world_file = opt->world;
    p.motion = load_settings(opt->config).motion;
    p.base = parse_base_pose(opt->base, "--base");
    p.ik_poses = opt->ik_poses;
    p.states = opt->states;
    p.goals = opt->goals;
    p.seed = opt->seed;
    const jobs::BenchMotionResult r = jobs::bench_motion(p);
    std::printf("kinematics (%d random poses)\n", opt->ik_poses);
    std::printf("  analytic IK, all branches         %8.3f us/solve  (%.2f solutions per pose)\n", r.ik_us,
                r.ik_solutions_per_pose);
    std::printf("  camera IK: limits, 2pi, sorting   %8.3f us/solve  (%.2f solutions per pose)\n", r.camera_ik_us,
                r.camera_ik_solutions_per_pose);
    std::printf("  forward kinematics (DH frame 6)   %8.3f us/call   (checksum %.3f)\n", r.fk_us, r.fk_checksum);
    std::printf("validity checks (%zu occupied voxels of %.3f m, base %s)\n", r.map_voxels, r.map_resolution_m,
                opt->base.c_str());
    std::printf("  random states                     %8.3f us/state  (%.1f%% in collision)\n", r.validity_us,
                100.0 * r.colliding_fraction);
    std::printf("  collision-free states only        %8.3f us/state  (every pair and shape checked)\n",
                r.validity_free_us);
    std::printf("planning (%s, %.2f s limit, %d random reachable goals from home)\n", r.planner.c_str(), r.time_limit_s,
                r.goals);
    std::printf("  success rate                      %8.1f %%  (%d straight-line, %d via OMPL)\n",
                100.0 * r.planned / r.goals, r.direct, r.planned - r.direct);
    std::printf("  time of successful plans          median %.1f ms, p90 %.1f ms, max %.1f ms\n", 1e3 * r.median_s,
                1e3 * r.p90_s, 1e3 * r.max_s);
    std::printf("  statuses:");
    for (const auto& [name, count] : r.statuses) std::printf(" %s %d", name.c_str(), count);
    std::printf("\n");
    if (!opt->json.empty()) {
      write_json_atomic(opt->json, r.to_json());
      spdlog::info("wrote {}", opt->json);
    }
  });
}

}  // namespace canopy::cli
