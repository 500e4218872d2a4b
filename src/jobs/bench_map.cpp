#include "canopy/jobs/bench_map.h"

#include <octomap/OcTree.h>

#include <algorithm>

#include "canopy/common/timer.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/jobs/world_job.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/sim/renderer.h"

namespace canopy::jobs {

namespace {

InsertTiming time_semantic(const std::vector<perception::LabelledCloud>& clouds, const mapping::SemanticMapParams& p,
                           const SemanticClasses& classes, int repeats) {
  InsertTiming t;
  for (int r = 0; r < repeats; ++r) {
    mapping::SemanticOcTree map(p, classes);
    mapping::ScanInserter ins(map);
    const Stopwatch watch;
    for (const auto& c : clouds) {
      const mapping::InsertStats st = ins.insert(c);
      t.filter_ms += st.ms_filter;
      t.raycast_ms += st.ms_raycast;
      t.update_ms += st.ms_update;
    }
    t.ms += watch.ms();
    t.nodes = map.size();
  }
  const double n = double(repeats) * double(clouds.size());
  t.ms /= n;
  t.filter_ms /= n;
  t.raycast_ms /= n;
  t.update_ms /= n;
  return t;
}

InsertTiming time_octomap(const std::vector<perception::LabelledCloud>& clouds, double res, double max_range,
                          int repeats) {
  std::vector<octomap::Pointcloud> octo;
  for (const auto& c : clouds) {
    octomap::Pointcloud pc;
    for (const Vec3f& p : c.points_world) pc.push_back(p.x(), p.y(), p.z());
    octo.push_back(std::move(pc));
  }
  InsertTiming t;
  for (int r = 0; r < repeats; ++r) {
    octomap::OcTree tree(res);
    const Stopwatch watch;
    for (std::size_t i = 0; i < octo.size(); ++i) {
      const Vec3& o = clouds[i].origin_world;
      tree.insertPointCloud(octo[i], octomap::point3d(float(o.x()), float(o.y()), float(o.z())), max_range,
                            /*lazy_eval=*/false, /*discretize=*/true);
    }
    t.ms += watch.ms();
    t.nodes = tree.size();
  }
  t.ms /= double(repeats) * double(clouds.size());
  return t;
}

InsertTimings time_all(const std::vector<perception::LabelledCloud>& clouds, const mapping::SemanticMapParams& p,
                       const SemanticClasses& classes, int repeats) {
  mapping::SemanticMapParams one = p, full = p;
  one.threads = 1;
  full.ray_range_m = p.max_range_m;
  InsertTimings t;
  t.octomap = time_octomap(clouds, p.resolution_m, p.max_range_m, repeats);
  t.semantic = time_semantic(clouds, p, classes, repeats);
  t.semantic_one = time_semantic(clouds, one, classes, repeats);
  t.semantic_full = time_semantic(clouds, full, classes, repeats);
  std::size_t points = 0;
  for (const auto& c : clouds) points += c.size();
  t.points_per_frame = clouds.empty() ? 0.0 : double(points) / double(clouds.size());
  return t;
}

}  // namespace

BenchMapResult bench_map(const BenchMapParams& params) {
  const world::WorldSpec spec = load_world_spec(params.world_file);
  const world::World world = build_world(spec);
  sim::Simulator sim(world, default_robot_config());
  sim::Renderer renderer(sim, spec.camera);
  const std::vector<Pose> views = params.views == "aisle"
                                      ? evaluation::aisle_views(world, std::max(1, params.frames / 2))
                                      : evaluation::views_from_spec(params.views, world);
  // Spread the frames over all plants.
  std::vector<Pose> picked;
  for (int i = 0; i < params.frames; ++i)
    picked.push_back(views[static_cast<std::size_t>(i) * views.size() / static_cast<std::size_t>(params.frames) %
                           views.size()]);
  perception::ExtractorParams ep = params.mapping.extractor;
  ep.source = perception::LabelSource::kTruth;
  perception::SemanticExtractor extractor(ep, spec.classes);
  std::vector<perception::LabelledCloud> clouds;
  for (const Pose& T : picked) clouds.push_back(extractor.extract(renderer.render_free_camera(T)));

  const mapping::SemanticMapParams& p = params.mapping.map;
  BenchMapResult r;
  r.world_name = spec.name;
  r.width_px = spec.camera.width_px;
  r.height_px = spec.camera.height_px;
  r.frames = static_cast<int>(clouds.size());
  r.resolution_m = p.resolution_m;
  r.max_range_m = p.max_range_m;
  r.ray_range_m = p.ray_range_m;
  r.rendered = time_all(clouds, p, spec.classes, params.repeats);

  std::vector<perception::LabelledCloud> walls;
  for (int i = 0; i < 8; ++i) {
    Image<float> depth(spec.camera.width_px, spec.camera.height_px, 0.9f);
    Image<std::uint8_t> labels(spec.camera.width_px, spec.camera.height_px, 1);
    const Pose T = picked[static_cast<std::size_t>(i) % picked.size()];
    walls.push_back(perception::depth_to_cloud(spec.camera, T, depth, labels, spec.classes.size()));
  }
  r.wall = time_all(walls, p, spec.classes, params.repeats);
  return r;
}

}  // namespace canopy::jobs
