// canopy bench render: time per frame (RGB + depth + labels) on a world, with frustum culling
// and with the full scene.

#include <spdlog/spdlog.h>

#include <cstdio>

#include "canopy/common/timer.h"
#include "canopy/sim/renderer.h"
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
    const world::WorldSpec spec = jobs::load_world_spec(opt->world);
    const world::World world = jobs::build_world(spec);
    sim::Simulator sim(world, default_robot_config());
    sim::RenderOptions ro;
    ro.shadows = opt->shadows;
    sim::Renderer renderer(sim, spec.camera, ro);
    // Views along the aisle looking at both rows, as the robot would see them.
    std::vector<Pose> views;
    const double x0 = spec.rows.x_start_m, x1 = x0 + (spec.rows.plants_per_row - 1) * spec.rows.plant_spacing_m;
    for (int i = 0; i < opt->frames; ++i) {
      const double s = opt->frames > 1 ? static_cast<double>(i) / (opt->frames - 1) : 0.5;
      const double side = i % 2 == 0 ? 1.0 : -1.0;
      const Vec3 eye(x0 + s * (x1 - x0), side * (spec.rows.row_offset_m - 0.45), 0.7);
      views.push_back(look_at(eye, eye + Vec3(0, side, 0)));
    }
    renderer.render_free_camera(views.front());  // warm-up (shader compilation, uploads)
    const int n = static_cast<int>(views.size());
    std::printf("bench render: world '%s', %zu plants, %dx%d, %d frames, shadows %s\n", spec.name.c_str(),
                world.plants.size(), spec.camera.width_px, spec.camera.height_px, n, opt->shadows ? "on" : "off");
    std::printf("  plant triangles: %zu\n", world.triangle_count());
    for (const bool culling : {true, false}) {
      renderer.set_culling(culling);
      double rgbd_ms = 0.0, full_ms = 0.0, triangles = 0.0, geoms = 0.0;
      for (const Pose& T : views) {
        Stopwatch watch;
        renderer.render(T, false, /*labels=*/false);
        rgbd_ms += watch.ms();
        watch.restart();
        renderer.render(T, false, /*labels=*/true);
        full_ms += watch.ms();
        triangles += static_cast<double>(renderer.last_triangle_count());
        geoms += renderer.last_drawn_geom_count();
      }
      std::printf("  %s: %.0f of %d geoms, %.0f triangles drawn per frame\n",
                  culling ? "frustum culling" : "full scene     ", geoms / n, renderer.last_scene_geom_count(),
                  triangles / n);
      std::printf("    RGB + depth:          %7.2f ms/frame\n", rgbd_ms / n);
      std::printf("    RGB + depth + labels: %7.2f ms/frame (budget 30 ms)\n", full_ms / n);
    }
  });
}

}  // namespace canopy::cli
