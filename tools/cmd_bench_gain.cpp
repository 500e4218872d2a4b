// canopy bench gain: time one view's information gain on a realistic map (a world mapped from
// a ring of views) for each ray set, with the fast traversal (flat voxel index) and the slow
// reference (computeRayKeys + a tree search per key) in the same run. The measuring is
// jobs::bench_gain (canopy/jobs/bench_gain.h); this file parses the flags and prints.

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>

#include "canopy/jobs/bench_gain.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_bench_gain(CLI::App& bench) {
  auto opt = std::make_shared<jobs::BenchGainParams>();
  opt->world_file = default_world_path();
  auto config = std::make_shared<std::string>(settings::default_settings_path());
  CLI::App* sub = bench.add_subcommand("gain", "Information gain per view for each ray set: fast traversal vs reference");
  sub->add_option("--world", opt->world_file, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", *config, kConfigHelp)->capture_default_str();
  sub->add_option("--views", opt->views, "Views that build the map: 'ring', 'aisle' or a pose file")->capture_default_str();
  sub->add_option("--gain", opt->gain, "Gain to time")->capture_default_str();
  sub->add_option("--candidates", opt->candidates, "Candidate views timed (spread over all clusters)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--min-ms", opt->min_ms, "Minimum time per measurement [ms]")->capture_default_str()->check(CLI::Range(1.0, 1e6));
  sub->callback([opt, config] {
    const jobs::BenchGainParams& o = *opt;
    const jobs::BenchGainResult r = jobs::bench_gain(o, load_settings(*config));
    std::printf("bench gain: world '%s', map from %zu '%s' views: %zu leaves, %zu known voxels (%zu occupied); "
                "index %zu bricks, %zu distinct states, %.1f MB, built in %.1f ms\n",
                r.world_name.c_str(), r.views, o.views.c_str(), r.counts.leaves, r.counts.voxels, r.counts.occupied,
                r.index_bricks, r.index_states, r.index_mb, r.index_build_ms);
    std::printf("  %zu clusters, %zu candidate views timed, gain '%s'\n", r.clusters, r.candidates, o.gain.c_str());
    std::printf("  (a) gain per view: traversal + voxel values + gain; the reference computes each voxel's values\n"
                "      from its tree state (p_occ, entropies, class distribution, MI terms)\n"
                "  (b) traversal returning p_occ and the class distribution per voxel (reference: computeRayKeys,\n"
                "      a tree search per key, SemanticState::occupancy + distribution)\n"
                "  (c) traversal only (keys and tree nodes; no values)\n");
    std::printf("  %-7s %6s %8s | %10s %10s %7s | %9s %9s %7s | %9s %9s %7s\n", "rays", "rays", "voxels", "(a) fast",
                "ref", "speedup", "(b) fast", "ref", "speedup", "(c) fast", "ref", "speedup");
    std::printf("  %-7s %6s %8s | %10s %10s %7s | %9s %9s %7s | %9s %9s %7s\n", "", "/view", "/view", "ms/view",
                "ms/view", "", "ns/vox", "ns/vox", "", "ns/vox", "ns/vox", "");
    for (const jobs::BenchGainRow& w : r.rows) {
      std::printf("  %-7s %6.0f %8.0f | %10.4f %10.4f %6.1fx | %9.1f %9.1f %6.1fx | %9.1f %9.1f %6.1fx\n",
                  w.rays.c_str(), w.rays_per_view, w.voxels_per_view, w.gain_ms_fast, w.gain_ms_reference,
                  w.gain_ms_reference / w.gain_ms_fast, w.values_ns_fast, w.values_ns_reference,
                  w.values_ns_reference / w.values_ns_fast, w.traverse_ns_fast, w.traverse_ns_reference,
                  w.traverse_ns_reference / w.traverse_ns_fast);
      if (std::fabs(w.gain_sum_fast - w.gain_sum_reference) > 1e-6 * std::max(1.0, std::fabs(w.gain_sum_reference)))
        spdlog::warn("{}: fast and reference gains differ ({} vs {})", w.rays, w.gain_sum_fast, w.gain_sum_reference);
    }
    std::printf("  gains with 'ours' rays, ms/view:");
    for (const auto& [name, ms] : r.gain_ms) std::printf(" %s %.4f", name.c_str(), ms);
    std::printf("\n");
  });
}

}  // namespace canopy::cli
