// canopy bench map: semantic insertion vs plain OctoMap insertPointCloud (discretize=true)
// on the same labelled clouds of rendered default-world frames, in the same run. The measuring
// is jobs::bench_map (jobs/bench_map.h); this file translates the flags and prints.

#include <spdlog/spdlog.h>

#include <cstdio>

#include "canopy/jobs/bench_map.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_bench_map(CLI::App& bench) {
  struct Options {
    std::string world = default_world_path();
    std::string config = settings::default_settings_path();
    std::string views = "ring";
    int frames = 32;
    int repeats = 3;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand("map", "Semantic insertion vs OctoMap insertPointCloud, ms per frame");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--views", opt->views, "Camera poses: 'ring', 'aisle' or a file of poses")->capture_default_str();
  sub->add_option("--frames", opt->frames, "Frames to insert, spread over the views")->capture_default_str()->check(CLI::Range(1, 10000));
  sub->add_option("--repeats", opt->repeats, "Runs over all frames, averaged")->capture_default_str()->check(CLI::Range(1, 100));
  sub->callback([opt] {
    jobs::BenchMapParams p;
    p.world_file = opt->world;
    p.mapping = load_settings(opt->config).mapping;
    p.views = opt->views;
    p.frames = opt->frames;
    p.repeats = opt->repeats;
    const jobs::BenchMapResult r = jobs::bench_map(p);
    const jobs::InsertTimings& t = r.rendered;
    spdlog::info("rendered {} frames, {:.0f} points per frame on average", r.frames, t.points_per_frame);
    std::printf("bench map: world '%s', views '%s', %d frames of %dx%d (%.0f points each), resolution %.3f m, %d repeats\n",
                r.world_name.c_str(), opt->views.c_str(), r.frames, r.width_px, r.height_px, t.points_per_frame,
                r.resolution_m, opt->repeats);
    std::printf("  OctoMap insertPointCloud (discretize, max range %.2f m):  %8.2f ms/frame  (%zu nodes)\n",
                r.max_range_m, t.octomap.ms, t.octomap.nodes);
    std::printf("  semantic, ray range %.2f m, all cores:                    %8.2f ms/frame  ratio %.3f  (%zu nodes)\n",
                r.ray_range_m, t.semantic.ms, t.semantic.ms / t.octomap.ms, t.semantic.nodes);
    std::printf("  semantic, ray range %.2f m, 1 thread:                     %8.2f ms/frame  ratio %.3f\n",
                r.ray_range_m, t.semantic_one.ms, t.semantic_one.ms / t.octomap.ms);
    std::printf("  semantic, ray range %.2f m (= OctoMap's), all cores:      %8.2f ms/frame  ratio %.3f  (%zu nodes)\n",
                r.max_range_m, t.semantic_full.ms, t.semantic_full.ms / t.octomap.ms, t.semantic_full.nodes);
    std::printf("  semantic phases (all cores): voxel filter %.2f, ray casting %.2f, tree update %.2f ms/frame\n",
                t.semantic.filter_ms, t.semantic.raycast_ms, t.semantic.update_ms);
    std::printf("  semantic phases (1 thread):  voxel filter %.2f, ray casting %.2f, tree update %.2f ms/frame\n",
                t.semantic_one.filter_ms, t.semantic_one.raycast_ms, t.semantic_one.update_ms);
    const jobs::InsertTimings& w = r.wall;
    std::printf("  wall at 0.9 m, %.0f points per frame: OctoMap %.2f ms/frame\n", w.points_per_frame, w.octomap.ms);
    std::printf("    semantic, ray range %.2f m: all cores %.2f ms (ratio %.3f), 1 thread %.2f ms (ratio %.3f)\n",
                r.ray_range_m, w.semantic.ms, w.semantic.ms / w.octomap.ms, w.semantic_one.ms,
                w.semantic_one.ms / w.octomap.ms);
    std::printf("    semantic, ray range %.2f m (= OctoMap's), all cores: %.2f ms (ratio %.3f)\n", r.max_range_m,
                w.semantic_full.ms, w.semantic_full.ms / w.octomap.ms);
  });
}

}  // namespace canopy::cli
