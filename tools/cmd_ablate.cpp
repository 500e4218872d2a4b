// canopy ablate: the paper's ablation (Fig. 5 and 6) with a free-moving camera (no arm).
// Parses the flags into an experiments::AblationPlan (the configuration matrix of
// experiments::ablation_matrix) and calls jobs::run_ablation_job (canopy/jobs/ablation_job.h),
// which runs it, draws the plots and publishes the folder; prints the table.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/jobs/ablation_job.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/ray_sets.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

// Splits "a,b,c", dropping empty items and repeats (a repeated configuration would have two
// workers write the same job file).
std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty() && std::find(out.begin(), out.end(), item) == out.end()) out.push_back(item);
  return out;
}

// Prints the table of summarize_ablation's rows.
void print_table(const std::vector<experiments::AblationRow>& rows, int views) {
  std::printf("\n%-28s %6s %14s %16s %10s %13s %10s\n", "configuration", "trials", "views->cov80", "per-plant mean",
              "reached", "raycast ms/v", "final cov");
  for (const auto& r : rows) {
    char reach[32];
    if (r.views_to_target_curve > 0) std::snprintf(reach, sizeof reach, "%d", r.views_to_target_curve);
    else std::snprintf(reach, sizeof reach, ">%d", views);
    std::printf("%-28s %6zu %14s %16.1f %5zu/%-4zu %13.4f %10.3f\n", r.config.id().c_str(), r.trials, reach,
                r.views_to_target_per_plant, r.runs_reaching, r.runs, r.raycast_ms_per_view, r.final_coverage);
  }
}

}  // namespace

void add_ablate_command(CLI::App& app) {
  struct Options {
    std::string world = "worlds/ablation.yaml";
    std::string config = settings::default_settings_path();
    int plants = 6, views = 30, trials = 10, initial_views = 2, threads = 2;
    std::string protocol = "paper";
    std::string proximity;
    double cluster_min_logodds = -1.0;
    std::string gains = "osamcep,ae,uvc,uvpc,oae,mi,rs";
    std::string rays = "ours,dense,sparse";
    std::string pgt = "1.0,0.7";
    std::string seg;
    std::uint64_t seed = 1;
    double coverage_target = 0.8;
    bool quick = false, resume = false, summarize_only = false, no_plots = false;
    std::vector<std::string> set, sweep;
    std::string out;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("ablate", "Free-camera ablation of gains and ray sets (paper Fig. 5 and 6)");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--plants", opt->plants, "Plants (the first N of the world)")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--views", opt->views, "Views per plant, initial ones included")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--trials", opt->trials, "Trials (seeded initial views)")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--protocol", opt->protocol,
                  "paper: 1 initial view from the 10-pose grid, rounds of every cluster's best view; one_view: "
                  "random initial views, one view per step")
      ->capture_default_str()
      ->check(CLI::IsMember({"paper", "one_view"}));
  sub->add_option("--cluster-min-logodds", opt->cluster_min_logodds,
                  "Cluster threshold replacing the settings' cluster.min_logodds (default: 0.5 with the paper "
                  "protocol: after its single initial view every fruit voxel has log-odds 1.0; the settings' value "
                  "with one_view)");
  sub->add_option("--initial-views", opt->initial_views, "Random initial views per plant (one_view protocol)")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--osamcep-proximity", opt->proximity,
                  "OSAMCEP proximity tests to compare (per_voxel,per_segment_end; default: the NBV settings')");
  sub->add_option("--set", opt->set, "A setting for every job, KEY=VALUE (e.g. mapping.map.ray_range_m=3.0); repeatable");
  sub->add_option("--sweep", opt->sweep,
                  "A setting compared over values, KEY=V1,V2 (each value a configuration); repeatable");
  sub->add_option("--gains", opt->gains, "Gains compared with our ray set")->capture_default_str();
  sub->add_option("--rays", opt->rays, "Ray sets compared with OSAMCEP")->capture_default_str();
  sub->add_option("--pgt", opt->pgt, "Segmentation P_gt values (1 = no noise)")->capture_default_str();
  sub->add_option("--seg", opt->seg, "Labels: color or truth (default from the mapping config)")->check(CLI::IsMember({"color", "truth"}));
  sub->add_option("--seed", opt->seed, "Base seed")->capture_default_str();
  sub->add_option("--threads", opt->threads, "Worker threads (one Simulator + Renderer each)")->capture_default_str()->check(CLI::Range(1, 64));
  sub->add_option("--coverage-target", opt->coverage_target, "Coverage for the views-to-target table")->capture_default_str()->check(CLI::Range(0.0, 1.0));
  sub->add_flag("--quick", opt->quick, "Small run: 1 plant, 6 views, 1 trial, osamcep+rs, ours+sparse, P_gt 1");
  sub->add_flag("--resume", opt->resume, "Reuse finished jobs found in --out");
  sub->add_flag("--summarize-only", opt->summarize_only, "Run no job: summarize the finished ones in --out");
  sub->add_flag("--no-plots", opt->no_plots, "Skip gains.svg and rays.svg");
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->callback([opt, sub] {
    const InterruptScope interrupts;  // Ctrl-C / SIGTERM: no new job starts, finished ones are kept
    Options o = *opt;
    if (o.quick) {  // small defaults; options given explicitly still win
      auto unset = [&](const char* name) { return sub->count(name) == 0; };
      if (unset("--plants")) o.plants = 1;
      if (unset("--views")) o.views = 6;
      if (unset("--trials")) o.trials = 1;
      if (unset("--gains")) o.gains = "osamcep,rs";
      if (unset("--rays")) o.rays = "ours,sparse";
      if (unset("--pgt")) o.pgt = "1.0";
    }
    // Validate everything before any work.
    settings::Settings bundle = load_settings(o.config);
    if (!o.seg.empty()) bundle.mapping.extractor.source = perception::label_source_from_string(o.seg, "--seg");
    apply_set_options(bundle, o.set);
    const std::vector<std::string> gains = split(o.gains), rays = split(o.rays);
    std::vector<double> pgts;
    for (const auto& s : split(o.pgt)) {
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (end == s.c_str() || *end != '\0' || !(v >= 0.0 && v <= 1.0))
        throw InputError("--pgt: value '" + s + "' is not a probability in [0, 1]");
      if (std::find(pgts.begin(), pgts.end(), v) == pgts.end()) pgts.push_back(v);
    }
    if (gains.empty() || rays.empty() || pgts.empty()) throw InputError("--gains, --rays and --pgt need a value each");
    for (const auto& g : gains) nbv::make_gain(g, bundle.nbv.gain, "--gains");
    for (const auto& r : rays) nbv::ray_set(r, "--rays");
    const std::vector<std::string> proximities = split(o.proximity);
    for (const auto& p : proximities) nbv::proximity_from_string(p, "--osamcep-proximity");
    std::vector<experiments::SettingSweep> sweeps;
    for (const std::string& s : o.sweep) {
      const settings::SettingOverride kv = settings::parse_override(s, "--sweep");
      experiments::SettingSweep sw{kv.first, split(kv.second)};
      for (const std::string& v : sw.values) {
        settings::Settings probe = bundle;
        probe.set(sw.key, v, "--sweep " + s);  // every value must be valid before any job runs
      }
      sweeps.push_back(sw);
    }

    jobs::AblationJobParams job;
    experiments::AblationPlan& plan = job.plan;
    plan.settings.protocol = experiments::ablation_protocol_from_string(o.protocol, "--protocol");
    plan.settings.views = o.views;
    plan.settings.initial_views = o.initial_views;
    if (o.initial_views > o.views) throw InputError("--initial-views: more than --views");
    plan.settings.cluster_min_logodds = o.cluster_min_logodds >= 0.0                                         ? o.cluster_min_logodds
                                        : plan.settings.protocol == experiments::AblationProtocol::kPaper ? 0.5
                                                                                                         : -1.0;
    plan.settings.seed = o.seed;
    plan.trials = o.trials;
    plan.plants = o.plants;
    plan.configs = experiments::ablation_matrix(gains, rays, pgts, proximities, sweeps);
    for (const auto& c : plan.configs) experiments::ablation_job_settings(bundle, c, plan.settings);  // validates

    job.world_file = o.world;
    job.out = o.out;
    job.run.threads = o.threads;
    job.run.resume = o.resume;
    job.run.summarize_only = o.summarize_only;
    job.run.coverage_target = o.coverage_target;
    job.run.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    job.run.stop_requested = [] { return interrupt_requested(); };
    job.plots = !o.no_plots;
    job.on_summary = [&o](const experiments::AblationRunResult& r) { print_table(r.rows, o.views); };
    const jobs::AblationJobResult r = jobs::run_ablation_job(job, bundle);
    std::printf("ablation done in %.0f s; wrote %s (summary.csv, table.csv, trials/, jobs/, gains.svg, rays.svg)\n", r.run.seconds,
                o.out.c_str());
    if (!r.zero_coverage.empty()) std::printf("%s\n", r.zero_coverage.c_str());
  });
}

}  // namespace canopy::cli
