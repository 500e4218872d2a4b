// canopy bench render: time per frame (RGB + depth + labels) on a world, with frustum culling
// and with the full scene. The measuring is jobs::bench_render (jobs/bench_render.h); this file
// translates the flags and prints.

#include <cstdio>

#include "canopy/jobs/bench_render.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_bench_render(CLI::App& bench) {
  struct Options {
    std::string world = default_world_path();
    int frames = 50;
    bool shadows = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand("render", "Milliseconds per frame (RGB + depth + labels) and triangle count");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--frames", opt->frames, "Frames to time")->capture_default_str()->check(CLI::Range(1, 100000));
  sub->add_flag("--shadows", opt->shadows, "Shadows in the RGB pass");
  sub->callback([opt] {
    jobs::BenchRenderParams p;
    p.world_file = opt->world;
    p.frames = opt->frames;
    p.shadows = opt->shadows;
    const jobs::BenchRenderResult r = jobs::bench_render(p);
    std::printf("bench render: world '%s', %zu plants, %dx%d, %d frames, shadows %s\n", r.world_name.c_str(), r.plants,
                r.width_px, r.height_px, r.frames, opt->shadows ? "on" : "off");
    std::printf("  plant triangles: %zu\n", r.plant_triangles);
    for (const jobs::RenderTiming& t : r.timings) {
      std::printf("  %s: %.0f of %d geoms, %.0f triangles drawn per frame\n",
                  t.culling ? "frustum culling" : "full scene     ", t.geoms, r.scene_geoms, t.triangles);
      std::printf("    RGB + depth:          %7.2f ms/frame\n", t.rgbd_ms);
      std::printf("    RGB + depth + labels: %7.2f ms/frame (budget 30 ms)\n", t.labelled_ms);
    }
  });
}

}  // namespace canopy::cli
