#include "canopy/jobs/bench_render.h"

#include "canopy/common/timer.h"
#include "canopy/jobs/world_job.h"
#include "canopy/sim/renderer.h"

namespace canopy::jobs {

BenchRenderResult bench_render(const BenchRenderParams& params) {
  const world::WorldSpec spec = load_world_spec(params.world_file);
  const world::World world = build_world(spec);
  sim::Simulator sim(world, default_robot_config());
  sim::RenderOptions ro;
  ro.shadows = params.shadows;
  sim::Renderer renderer(sim, spec.camera, ro);
  // Views along the aisle looking at both rows, as the robot would see them.
  std::vector<Pose> views;
  const double x0 = spec.rows.x_start_m, x1 = x0 + (spec.rows.plants_per_row - 1) * spec.rows.plant_spacing_m;
  for (int i = 0; i < params.frames; ++i) {
    const double s = params.frames > 1 ? static_cast<double>(i) / (params.frames - 1) : 0.5;
    const double side = i % 2 == 0 ? 1.0 : -1.0;
    const Vec3 eye(x0 + s * (x1 - x0), side * (spec.rows.row_offset_m - 0.45), 0.7);
    views.push_back(look_at(eye, eye + Vec3(0, side, 0)));
  }
  renderer.render_free_camera(views.front());  // warm-up (shader compilation, uploads)
  BenchRenderResult r;
  r.world_name = spec.name;
  r.plants = world.plants.size();
  r.plant_triangles = world.triangle_count();
  r.width_px = spec.camera.width_px;
  r.height_px = spec.camera.height_px;
  r.frames = static_cast<int>(views.size());
  for (const bool culling : {true, false}) {
    renderer.set_culling(culling);
    RenderTiming t;
    t.culling = culling;
    for (const Pose& T : views) {
      Stopwatch watch;
      renderer.render(T, false, /*labels=*/false);
      t.rgbd_ms += watch.ms();
      watch.restart();
      renderer.render(T, false, /*labels=*/true);
      t.labelled_ms += watch.ms();
      t.triangles += static_cast<double>(renderer.last_triangle_count());
      t.geoms += renderer.last_drawn_geom_count();
    }
    const double n = static_cast<double>(views.size());
    t.rgbd_ms /= n;
    t.labelled_ms /= n;
    t.triangles /= n;
    t.geoms /= n;
    r.scene_geoms = renderer.last_scene_geom_count();
    r.timings.push_back(t);
  }
  return r;
}

}  // namespace canopy::jobs
