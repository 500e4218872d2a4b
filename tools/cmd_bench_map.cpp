// canopy bench map: semantic insertion vs plain OctoMap insertPointCloud (discretize=true)
// on the same labelled clouds of rendered default-world frames, in the same run.

#include <octomap/OcTree.h>
#include <spdlog/spdlog.h>

#include <cstdio>

#include "canopy/common/timer.h"
#include "canopy/settings/settings.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/sim/renderer.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {


struct Timing {
  double ms = 0.0;
  double filter_ms = 0.0, raycast_ms = 0.0, update_ms = 0.0;  // semantic phases
  std::size_t nodes = 0;
};

Timing time_semantic(const std::vector<perception::LabelledCloud>& clouds, const mapping::SemanticMapParams& p,
                     const SemanticClasses& classes, int repeats) {
  Timing t;
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

Timing time_octomap(const std::vector<octomap::Pointcloud>& clouds, const std::vector<Vec3>& origins, double res,
                    double max_range, int repeats) {
  Timing t;
  for (int r = 0; r < repeats; ++r) {
    octomap::OcTree tree(res);
    const Stopwatch watch;
    for (std::size_t i = 0; i < clouds.size(); ++i) {
      const octomap::point3d o(float(origins[i].x()), float(origins[i].y()), float(origins[i].z()));
      tree.insertPointCloud(clouds[i], o, max_range, /*lazy_eval=*/false, /*discretize=*/true);
    }
    t.ms += watch.ms();
    t.nodes = tree.size();
  }
  t.ms /= double(repeats) * double(clouds.size());
  return t;
}

}  // namespace

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
    const settings::MappingSettings cfg = load_settings(opt->config).mapping;
    const world::WorldSpec spec = jobs::load_world_spec(opt->world);
    const world::World world = jobs::build_world(spec);
    sim::Simulator sim(world, default_robot_config());
    sim::Renderer renderer(sim, spec.camera);
    const std::vector<Pose> views = opt->views == "aisle" ? evaluation::aisle_views(world, std::max(1, opt->frames / 2))
                                                          : evaluation::views_from_spec(opt->views, world);
    // Spread the frames over all plants.
    std::vector<Pose> picked;
    for (int i = 0; i < opt->frames; ++i)
      picked.push_back(views[static_cast<std::size_t>(i) * views.size() / static_cast<std::size_t>(opt->frames) % views.size()]);
    perception::ExtractorParams ep = cfg.extractor;
    ep.source = perception::LabelSource::kTruth;
    perception::SemanticExtractor extractor(ep, spec.classes);
    std::vector<perception::LabelledCloud> clouds;
    std::vector<octomap::Pointcloud> octo;
    std::vector<Vec3> origins;
    std::size_t points = 0;
    for (const Pose& T : picked) {
      clouds.push_back(extractor.extract(renderer.render_free_camera(T)));
      octomap::Pointcloud pc;
      for (const Vec3f& p : clouds.back().points_world) pc.push_back(p.x(), p.y(), p.z());
      octo.push_back(std::move(pc));
      origins.push_back(clouds.back().origin_world);
      points += clouds.back().size();
    }
    const int n = static_cast<int>(clouds.size());
    spdlog::info("rendered {} frames, {:.0f} points per frame on average", n, double(points) / n);

    const mapping::SemanticMapParams p = cfg.map;
    mapping::SemanticMapParams p1 = p, pfull = p;
    p1.threads = 1;
    pfull.ray_range_m = p.max_range_m;
    const Timing octomap_t = time_octomap(octo, origins, p.resolution_m, p.max_range_m, opt->repeats);
    const Timing sem = time_semantic(clouds, p, spec.classes, opt->repeats);
    const Timing sem1 = time_semantic(clouds, p1, spec.classes, opt->repeats);
    const Timing semfull = time_semantic(clouds, pfull, spec.classes, opt->repeats);

    std::printf("bench map: world '%s', views '%s', %d frames of %dx%d (%.0f points each), resolution %.3f m, %d repeats\n",
                spec.name.c_str(), opt->views.c_str(), n, spec.camera.width_px, spec.camera.height_px, double(points) / n,
                p.resolution_m, opt->repeats);
    std::printf("  OctoMap insertPointCloud (discretize, max range %.2f m):  %8.2f ms/frame  (%zu nodes)\n",
                p.max_range_m, octomap_t.ms, octomap_t.nodes);
    std::printf("  semantic, ray range %.2f m, all cores:                    %8.2f ms/frame  ratio %.3f  (%zu nodes)\n",
                p.ray_range_m, sem.ms, sem.ms / octomap_t.ms, sem.nodes);
    std::printf("  semantic, ray range %.2f m, 1 thread:                     %8.2f ms/frame  ratio %.3f\n",
                p.ray_range_m, sem1.ms, sem1.ms / octomap_t.ms);
    std::printf("  semantic, ray range %.2f m (= OctoMap's), all cores:      %8.2f ms/frame  ratio %.3f  (%zu nodes)\n",
                pfull.ray_range_m, semfull.ms, semfull.ms / octomap_t.ms, semfull.nodes);
    std::printf("  semantic phases (all cores): voxel filter %.2f, ray casting %.2f, tree update %.2f ms/frame\n",
                sem.filter_ms, sem.raycast_ms, sem.update_ms);
    std::printf("  semantic phases (1 thread):  voxel filter %.2f, ray casting %.2f, tree update %.2f ms/frame\n",
                sem1.filter_ms, sem1.raycast_ms, sem1.update_ms);

    // docs/background/speed_anchors.md's anchor: a full 400x400 frame of a wall 0.9 m away (every pixel
    // valid), where the dense part of the work, and the second core, count.
    std::vector<perception::LabelledCloud> walls;
    std::vector<octomap::Pointcloud> wall_octo;
    std::vector<Vec3> wall_origins;
    for (int i = 0; i < 8; ++i) {
      Image<float> depth(spec.camera.width_px, spec.camera.height_px, 0.9f);
      Image<std::uint8_t> labels(spec.camera.width_px, spec.camera.height_px, 1);
      Pose T = picked[static_cast<std::size_t>(i) % picked.size()];
      walls.push_back(perception::depth_to_cloud(spec.camera, T, depth, labels, spec.classes.size()));
      octomap::Pointcloud pc;
      for (const Vec3f& q : walls.back().points_world) pc.push_back(q.x(), q.y(), q.z());
      wall_octo.push_back(std::move(pc));
      wall_origins.push_back(walls.back().origin_world);
    }
    const Timing wall_octomap = time_octomap(wall_octo, wall_origins, p.resolution_m, p.max_range_m, opt->repeats);
    const Timing wall_sem = time_semantic(walls, p, spec.classes, opt->repeats);
    const Timing wall_sem1 = time_semantic(walls, p1, spec.classes, opt->repeats);
    const Timing wall_full = time_semantic(walls, pfull, spec.classes, opt->repeats);
    std::printf("  wall at 0.9 m, %zu points per frame: OctoMap %.2f ms/frame\n", walls.front().size(), wall_octomap.ms);
    std::printf("    semantic, ray range %.2f m: all cores %.2f ms (ratio %.3f), 1 thread %.2f ms (ratio %.3f)\n",
                p.ray_range_m, wall_sem.ms, wall_sem.ms / wall_octomap.ms, wall_sem1.ms, wall_sem1.ms / wall_octomap.ms);
    std::printf("    semantic, ray range %.2f m (= OctoMap's), all cores: %.2f ms (ratio %.3f)\n", pfull.ray_range_m,
                wall_full.ms, wall_full.ms / wall_octomap.ms);
  });
}

}  // namespace canopy::cli
