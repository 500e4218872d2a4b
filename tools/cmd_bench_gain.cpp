// canopy bench gain: time one view's information gain on a realistic map (a world mapped from
// a ring of views) for each ray set, with the fast traversal (flat voxel index) and the slow
// reference (computeRayKeys + a tree search per key) in the same run.

#include <spdlog/spdlog.h>

#include <cstdio>

#include "canopy/common/timer.h"
#include "canopy/mission/settings.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/nbv/planner.h"
#include "canopy/sim/renderer.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {


struct Timed {
  double ms_per_view = 0.0;
  double voxels_per_view = 0.0;
  double gain_sum = 0.0;
};

// Repeats `pass` (one pass over all views) until min_ms elapsed; ms per view.
template <typename F>
Timed time_views(std::size_t views, double min_ms, F&& pass) {
  Timed t;
  int reps = 0;
  std::size_t voxels = 0;
  const Stopwatch watch;
  double elapsed = 0.0;
  do {
    double g = 0.0;
    voxels += pass(&g);
    t.gain_sum = g;
    ++reps;
    elapsed = watch.ms();
  } while (elapsed < min_ms);
  t.ms_per_view = elapsed / (double(reps) * double(views));
  t.voxels_per_view = double(voxels) / (double(reps) * double(views));
  return t;
}

}  // namespace

void add_bench_gain(CLI::App& bench) {
  struct Options {
    std::string world = default_world_path();
    std::string config = mission::default_settings_path();
    std::string views = "ring";
    std::string gain = "osamcep";
    int candidates = 200;
    double min_ms = 400.0;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand("gain", "Information gain per view for each ray set: fast traversal vs reference");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--views", opt->views, "Views that build the map: 'ring', 'aisle' or a pose file")->capture_default_str();
  sub->add_option("--gain", opt->gain, "Gain to time")->capture_default_str();
  sub->add_option("--candidates", opt->candidates, "Candidate views timed (spread over all clusters)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--min-ms", opt->min_ms, "Minimum time per measurement [ms]")->capture_default_str()->check(CLI::Range(1.0, 1e6));
  sub->callback([opt] {
    const mission::Settings bundle = load_settings(opt->config);
    const mission::MappingSettings cfg = bundle.mapping;
    const nbv::NbvParams np = bundle.nbv;
    const auto gain = nbv::make_gain(opt->gain, np.gain, "--gain");
    const world::WorldSpec spec = load_world_spec(opt->world);
    const world::World world = build_world(spec);
    const std::vector<Pose> views = evaluation::views_from_spec(opt->views, world);

    // The map.
    sim::Simulator sim(world, default_robot_config());
    sim::Renderer renderer(sim, spec.camera);
    mapping::SemanticOcTree map(cfg.map, spec.classes);
    mapping::ScanInserter inserter(map);
    perception::SemanticExtractor extractor(cfg.extractor, spec.classes);
    const Stopwatch mapping_watch;
    for (const Pose& T : views) inserter.insert(extractor.extract(renderer.render_free_camera(T)));
    spdlog::info("mapped {} views in {:.1f} s", views.size(), mapping_watch.seconds());
    nbv::VoxelIndex index(map);
    const mapping::VoxelCounts counts = map.counts();
    const auto clusters = nbv::find_clusters(map, np.cluster);

    // Candidates spread over all clusters.
    std::vector<nbv::Candidate> all;
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      const auto cs = nbv::sample_candidates(clusters[c].centroid, int(c), np.candidates);
      all.insert(all.end(), cs.begin(), cs.end());
    }
    if (all.empty()) throw InputError("bench gain: the map of '" + opt->world + "' has no fruit clusters");
    std::vector<nbv::Candidate> cands;
    const std::size_t n = std::min<std::size_t>(all.size(), std::size_t(opt->candidates));
    for (std::size_t i = 0; i < n; ++i) cands.push_back(all[i * all.size() / n]);

    std::printf("bench gain: world '%s', map from %zu '%s' views: %zu leaves, %zu known voxels (%zu occupied); "
                "index %zu bricks, %zu distinct states, %.1f MB, built in %.1f ms\n",
                spec.name.c_str(), views.size(), opt->views.c_str(), counts.leaves, counts.voxels, counts.occupied,
                index.brick_count(), index.palette_size(), index.memory_bytes() / 1e6, index.build_ms());
    std::printf("  %zu clusters, %zu candidate views timed, gain '%s'\n", clusters.size(), cands.size(),
                opt->gain.c_str());
    std::printf("  (a) gain per view: traversal + voxel values + gain; the reference computes each voxel's values\n"
                "      from its tree state (p_occ, entropies, class distribution, MI terms)\n"
                "  (b) traversal returning p_occ and the class distribution per voxel (reference: computeRayKeys,\n"
                "      a tree search per key, SemanticState::occupancy + distribution)\n"
                "  (c) traversal only (keys and tree nodes; no values)\n");
    std::printf("  %-7s %6s %8s | %10s %10s %7s | %9s %9s %7s | %9s %9s %7s\n", "rays", "rays", "voxels", "(a) fast",
                "ref", "speedup", "(b) fast", "ref", "speedup", "(c) fast", "ref", "speedup");
    std::printf("  %-7s %6s %8s | %10s %10s %7s | %9s %9s %7s | %9s %9s %7s\n", "", "/view", "/view", "ms/view",
                "ms/view", "", "ns/vox", "ns/vox", "", "ns/vox", "ns/vox", "");
    nbv::ViewEvaluator eval(index, spec.camera, np.rays);
    for (const auto& rname : nbv::ray_set_names()) {
      const nbv::RaySetEntry& rays = nbv::ray_set(rname);
      // (a) The same candidates through the fast evaluator and through the reference.
      auto time_gain = [&](bool reference) {
        return time_views(cands.size(), opt->min_ms, [&](double* g) {
          std::size_t vox = 0;
          for (std::size_t i = 0; i < cands.size(); ++i) {
            const auto s = reference ? eval.evaluate_reference(cands[i].T_world_camera, cands[i].target, *gain, rays, i)
                                     : eval.evaluate(cands[i].T_world_camera, cands[i].target, *gain, rays, i);
            *g += s.gain;
            vox += s.voxels;
          }
          return vox;
        });
      };
      const Timed fast = time_gain(false);
      const Timed ref = time_gain(true);
      // Traversal only, on the same segments.
      std::vector<std::vector<Vec3>> ends(cands.size());
      std::size_t rays_total = 0;
      for (std::size_t i = 0; i < cands.size(); ++i) {
        nbv::ViewStatus st;
        eval.ray_segments(cands[i].T_world_camera, cands[i].target, rays, &ends[i], &st);
        rays_total += ends[i].size();
      }
      std::vector<nbv::RayVoxel> buf(index.max_voxels(2.0));
      const Timed tfast = time_views(cands.size(), opt->min_ms, [&](double* g) {
        std::size_t vox = 0;
        for (std::size_t i = 0; i < cands.size(); ++i)
          for (const Vec3& e : ends[i]) {
            const std::size_t k = index.cast(cands[i].T_world_camera.translation(), e, cands[i].target, buf.data(), buf.size());
            vox += k;
            if (k) *g += buf[k - 1].info->p_occ;
          }
        return vox;
      });
      octomap::KeyRay key_ray;
      std::vector<nbv::ReferenceVoxel> rv;
      const Timed tref = time_views(cands.size(), opt->min_ms, [&](double* g) {
        std::size_t vox = 0;
        for (std::size_t i = 0; i < cands.size(); ++i)
          for (const Vec3& e : ends[i]) {
            rv.clear();
            nbv::cast_reference(map, cands[i].T_world_camera.translation(), e, &key_ray, &rv);
            vox += rv.size();
            if (!rv.empty() && rv.back().state) *g += rv.back().state->occupancy_logodds();
          }
        return vox;
      });
      // Traversal with p_occ and the class distribution per voxel.
      const int K = map.num_classes();
      const Timed vfast = time_views(cands.size(), opt->min_ms, [&](double* g) {
        std::size_t vox = 0;
        for (std::size_t i = 0; i < cands.size(); ++i)
          for (const Vec3& e : ends[i]) {
            const std::size_t k = index.cast(cands[i].T_world_camera.translation(), e, cands[i].target, buf.data(), buf.size());
            vox += k;
            for (std::size_t m = 0; m < k; ++m) {
              const nbv::VoxelInfo& x = *buf[m].info;
              double s = x.p_occ;
              for (int c = 0; c <= K; ++c) s += x.prob[c];
              *g += s;
            }
          }
        return vox;
      });
      double dist[nbv::VoxelInfo::kMaxCategories];
      const Timed vref = time_views(cands.size(), opt->min_ms, [&](double* g) {
        std::size_t vox = 0;
        for (std::size_t i = 0; i < cands.size(); ++i)
          for (const Vec3& e : ends[i]) {
            rv.clear();
            nbv::cast_reference(map, cands[i].T_world_camera.translation(), e, &key_ray, &rv);
            vox += rv.size();
            for (const auto& r : rv) {
              double s = 0.5;
              if (r.state) {
                s = r.state->occupancy();
                r.state->distribution(K, dist);
              } else {
                mapping::SemanticState{}.distribution(K, dist);
              }
              for (int c = 0; c <= K; ++c) s += dist[c];
              *g += s;
            }
          }
        return vox;
      });
      auto ns = [](const Timed& t) { return t.ms_per_view * 1e6 / std::max(1.0, t.voxels_per_view); };
      std::printf("  %-7s %6.0f %8.0f | %10.4f %10.4f %6.1fx | %9.1f %9.1f %6.1fx | %9.1f %9.1f %6.1fx\n",
                  rname.c_str(), double(rays_total) / double(cands.size()), fast.voxels_per_view, fast.ms_per_view,
                  ref.ms_per_view, ref.ms_per_view / fast.ms_per_view, ns(vfast), ns(vref), ns(vref) / ns(vfast),
                  ns(tfast), ns(tref), ns(tref) / ns(tfast));
      if (std::fabs(fast.gain_sum - ref.gain_sum) > 1e-6 * std::max(1.0, std::fabs(ref.gain_sum)))
        spdlog::warn("{}: fast and reference gains differ ({} vs {})", rname, fast.gain_sum, ref.gain_sum);
    }
    // Every gain with our ray set.
    std::printf("  gains with 'ours' rays, ms/view:");
    for (const auto& gname : nbv::gain_names()) {
      const auto g = nbv::make_gain(gname, np.gain);
      const Timed t = time_views(cands.size(), opt->min_ms / 4, [&](double* s) {
        for (std::size_t i = 0; i < cands.size(); ++i)
          *s += eval.evaluate(cands[i].T_world_camera, cands[i].target, *g, nbv::ray_set("ours"), i).gain;
        return std::size_t(0);
      });
      std::printf(" %s %.4f", gname.c_str(), t.ms_per_view);
    }
    std::printf("\n");
  });
}

}  // namespace canopy::cli
