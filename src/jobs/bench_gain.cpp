#include "canopy/jobs/bench_gain.h"

#include <spdlog/spdlog.h>

#include "canopy/common/error.h"
#include "canopy/common/timer.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/jobs/world_job.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/view_evaluator.h"
#include "canopy/sim/renderer.h"

namespace canopy::jobs {

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

double ns_per_voxel(const Timed& t) { return t.ms_per_view * 1e6 / std::max(1.0, t.voxels_per_view); }

// The timings of one ray set on `cands`.
class RaySetBench {
 public:
  RaySetBench(const mapping::SemanticOcTree& map, const nbv::VoxelIndex& index, nbv::ViewEvaluator& eval,
              const std::vector<nbv::Candidate>& cands, double min_ms)
      : map_(map), index_(index), eval_(eval), cands_(cands), min_ms_(min_ms), buf_(index.max_voxels(2.0)) {}

  BenchGainRow run(const std::string& name, const nbv::GainFunction& gain) {
    const nbv::RaySetEntry& rays = nbv::ray_set(name);
    BenchGainRow row;
    row.rays = name;
    // (a) The same candidates through the fast evaluator and through the reference.
    const Timed fast = time_gain(gain, rays, false), ref = time_gain(gain, rays, true);
    row.voxels_per_view = fast.voxels_per_view;
    row.gain_ms_fast = fast.ms_per_view;
    row.gain_ms_reference = ref.ms_per_view;
    row.gain_sum_fast = fast.gain_sum;
    row.gain_sum_reference = ref.gain_sum;
    // Traversal only, on the same segments.
    ends_.assign(cands_.size(), {});
    std::size_t rays_total = 0;
    for (std::size_t i = 0; i < cands_.size(); ++i) {
      nbv::ViewStatus st;
      eval_.ray_segments(cands_[i].T_world_camera, cands_[i].target, rays, &ends_[i], &st);
      rays_total += ends_[i].size();
    }
    row.rays_per_view = double(rays_total) / double(cands_.size());
    row.traverse_ns_fast = ns_per_voxel(traverse_fast(false));
    row.traverse_ns_reference = ns_per_voxel(traverse_reference(false));
    // Traversal with p_occ and the class distribution per voxel.
    row.values_ns_fast = ns_per_voxel(traverse_fast(true));
    row.values_ns_reference = ns_per_voxel(traverse_reference(true));
    return row;
  }

 private:
  Timed time_gain(const nbv::GainFunction& gain, const nbv::RaySetEntry& rays, bool reference) {
    return time_views(cands_.size(), min_ms_, [&](double* g) {
      std::size_t vox = 0;
      for (std::size_t i = 0; i < cands_.size(); ++i) {
        const auto& c = cands_[i];
        const auto s = reference ? eval_.evaluate_reference(c.T_world_camera, c.target, gain, rays, i)
                                 : eval_.evaluate(c.T_world_camera, c.target, gain, rays, i);
        *g += s.gain;
        vox += s.voxels;
      }
      return vox;
    });
  }

  // The flat index's traversal; with `values` it reads p_occ and the class distribution per voxel.
  Timed traverse_fast(bool values) {
    const int K = map_.num_classes();
    return time_views(cands_.size(), min_ms_, [&](double* g) {
      std::size_t vox = 0;
      for (std::size_t i = 0; i < cands_.size(); ++i)
        for (const Vec3& e : ends_[i]) {
          const std::size_t k =
              index_.cast(cands_[i].T_world_camera.translation(), e, cands_[i].target, buf_.data(), buf_.size());
          vox += k;
          if (!values) {
            if (k) *g += buf_[k - 1].info->p_occ;
            continue;
          }
          for (std::size_t m = 0; m < k; ++m) {
            const nbv::VoxelInfo& x = *buf_[m].info;
            double s = x.p_occ;
            for (int c = 0; c <= K; ++c) s += x.prob[c];
            *g += s;
          }
        }
      return vox;
    });
  }

  // The reference traversal (computeRayKeys + a tree search per key), likewise.
  Timed traverse_reference(bool values) {
    const int K = map_.num_classes();
    double dist[nbv::VoxelInfo::kMaxCategories];
    return time_views(cands_.size(), min_ms_, [&](double* g) {
      std::size_t vox = 0;
      for (std::size_t i = 0; i < cands_.size(); ++i)
        for (const Vec3& e : ends_[i]) {
          rv_.clear();
          nbv::cast_reference(map_, cands_[i].T_world_camera.translation(), e, &key_ray_, &rv_);
          vox += rv_.size();
          if (!values) {
            if (!rv_.empty() && rv_.back().state) *g += rv_.back().state->occupancy_logodds();
            continue;
          }
          for (const auto& r : rv_) {
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
  }

  const mapping::SemanticOcTree& map_;
  const nbv::VoxelIndex& index_;
  nbv::ViewEvaluator& eval_;
  const std::vector<nbv::Candidate>& cands_;
  double min_ms_;
  std::vector<nbv::RayVoxel> buf_;
  std::vector<std::vector<Vec3>> ends_;
  octomap::KeyRay key_ray_;
  std::vector<nbv::ReferenceVoxel> rv_;
};

}  // namespace

BenchGainResult bench_gain(const BenchGainParams& params, const settings::Settings& bundle) {
  const settings::MappingSettings& cfg = bundle.mapping;
  const nbv::NbvParams& np = bundle.nbv;
  const auto gain = nbv::make_gain(params.gain, np.gain, "--gain");
  const world::WorldSpec spec = load_world_spec(params.world_file);
  const world::World world = build_world(spec);
  const std::vector<Pose> views = evaluation::views_from_spec(params.views, world);

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
  const auto clusters = nbv::find_clusters(map, np.cluster);

  // Candidates spread over all clusters.
  std::vector<nbv::Candidate> all;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    const auto cs = nbv::sample_candidates(clusters[c].centroid, int(c), np.candidates);
    all.insert(all.end(), cs.begin(), cs.end());
  }
  if (all.empty()) throw InputError("bench gain: the map of '" + params.world_file + "' has no fruit clusters");
  std::vector<nbv::Candidate> cands;
  const std::size_t n = std::min<std::size_t>(all.size(), std::size_t(params.candidates));
  for (std::size_t i = 0; i < n; ++i) cands.push_back(all[i * all.size() / n]);

  BenchGainResult r;
  r.world_name = spec.name;
  r.views = views.size();
  r.counts = map.counts();
  r.index_bricks = index.brick_count();
  r.index_states = index.palette_size();
  r.index_mb = index.memory_bytes() / 1e6;
  r.index_build_ms = index.build_ms();
  r.clusters = clusters.size();
  r.candidates = cands.size();
  nbv::ViewEvaluator eval(index, spec.camera, np.rays);
  RaySetBench bench(map, index, eval, cands, params.min_ms);
  for (const auto& rname : nbv::ray_set_names()) r.rows.push_back(bench.run(rname, *gain));
  // Every gain with our ray set.
  for (const auto& gname : nbv::gain_names()) {
    const auto g = nbv::make_gain(gname, np.gain);
    const Timed t = time_views(cands.size(), params.min_ms / 4, [&](double* s) {
      for (std::size_t i = 0; i < cands.size(); ++i)
        *s += eval.evaluate(cands[i].T_world_camera, cands[i].target, *g, nbv::ray_set("ours"), i).gain;
      return std::size_t(0);
    });
    r.gain_ms.emplace_back(gname, t.ms_per_view);
  }
  return r;
}

}  // namespace canopy::jobs
