// canopy ablate: the paper's ablation (Fig. 5 and 6) with a free-moving camera (no arm).
// For each configuration (a gain with our ray set, or OSAMCEP with another ray set; each at
// every P_gt), trial and plant, experiments::run_ablation_job runs one job (its rules are in
// canopy/experiments/ablation.h). Jobs run on worker threads, each with its own Simulator and
// Renderer; a job's result depends only on its seeds, not on the thread or the job order.
// Every finished job is written at once (jobs/<config>/trial<t>_plant<p>.json; --resume
// reuses them), then per-trial JSONs, summary.csv, table.csv and PNG plots.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/common/io.h"
#include "canopy/common/process.h"
#include "canopy/common/random.h"
#include "canopy/mapping/mapping_config.h"
#include "canopy/experiments/ablation.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/ray_sets.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using experiments::AblationConfig;
using Job = experiments::AblationJobId;

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
    std::string config = mission::default_settings_path();
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
  sub->add_flag("--no-plots", opt->no_plots, "Skip the PNG plots");
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->callback([opt, sub] {
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
    mission::Settings bundle = load_settings(o.config);
    const mapping::MappingConfig& mcfg = bundle.mapping;
    if (!o.seg.empty()) bundle.mapping.extractor.source = perception::label_source_from_string(o.seg, "--seg");
    const nbv::NbvParams np = bundle.nbv;
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
    for (const auto& g : gains) nbv::make_gain(g, np.gain, "--gains");
    for (const auto& r : rays) nbv::ray_set(r, "--rays");
    std::vector<std::string> proximities = split(o.proximity);
    for (const auto& p : proximities) nbv::proximity_from_string(p, "--osamcep-proximity");
    if (proximities.empty()) proximities.push_back("");
    const experiments::AblationProtocol protocol = experiments::ablation_protocol_from_string(o.protocol, "--protocol");
    if (o.initial_views > o.views) throw InputError("--initial-views: more than --views");
    world::WorldSpec spec = load_world_spec(o.world);
    spec.camera.depth_noise_k = 0.0;  // segmentation noise only, and renderers stay stateless
    const world::World world = world::generate_world(spec);
    if (o.plants > int(world.plants.size()))
      throw InputError("--plants: " + std::to_string(o.plants) + " but the world has " +
                       std::to_string(world.plants.size()));

    // Configurations: every gain with our ray set (or the first given), OSAMCEP (or the first
    // gain) with every other ray set; each at every P_gt.
    const std::string main_rays = std::find(rays.begin(), rays.end(), "ours") != rays.end() ? "ours" : rays[0];
    const std::string main_gain = std::find(gains.begin(), gains.end(), "osamcep") != gains.end() ? "osamcep" : gains[0];
    std::vector<AblationConfig> configs;
    // OSAMCEP runs once per proximity test asked for.
    auto variants = [&](const std::string& g) {
      return g == "osamcep" ? proximities : std::vector<std::string>{""};
    };
    for (double p : pgts) {
      for (const auto& g : gains)
        for (const auto& x : variants(g)) configs.push_back({g, main_rays, p, x});
      for (const auto& r : rays)
        if (r != main_rays)
          for (const auto& x : variants(main_gain)) configs.push_back({main_gain, r, p, x});
    }
    std::vector<Job> jobs;  // trial-major, so an interrupted run has whole trials
    for (int t = 0; t < o.trials; ++t)
      for (std::size_t c = 0; c < configs.size(); ++c)
        for (int p = 0; p < o.plants; ++p) jobs.push_back({c, t, p});

    // Only --resume (or --summarize-only) adds to an existing folder; a fresh run replaces it.
    const bool reuse = o.resume || o.summarize_only;
    StagedDir out_dir(o.out, reuse ? StagedDir::Mode::kResume : StagedDir::Mode::kReplace);
    const std::string out = out_dir.working_dir();
    nlohmann::json settings = {{"world", spec.name},   {"plants", o.plants},         {"views", o.views},
                               {"trials", o.trials},   {"initial_views", o.initial_views},
                               {"protocol", o.protocol}, {"osamcep_proximity", o.proximity},
                               {"cluster_min_logodds", o.cluster_min_logodds},
                               {"seed", o.seed},       {"threads", o.threads},       {"labels", perception::to_string(mcfg.extractor.source)}};
    YAML::Emitter e1, e2;
    e1 << mcfg.to_yaml();
    e2 << np.to_yaml();
    settings["mapping_config"] = std::string(e1.c_str());
    settings["nbv_config"] = std::string(e2.c_str());
    if (reuse) {
      // Finished jobs are only reused from a run with the same settings (threads aside).
      std::ifstream previous_file(out + "/settings.json");
      if (previous_file) {
        nlohmann::json previous;
        try {
          previous = nlohmann::json::parse(previous_file);
        } catch (const std::exception&) {
          throw InputError("--resume: " + o.out + "/settings.json is not valid JSON");
        }
        nlohmann::json a = settings, b = previous;
        a.erase("threads");
        b.erase("threads");
        if (a != b)
          throw InputError("--resume: the settings differ from those of the run in " + o.out +
                           " (world, plants, views, trials, seed, labels or configs); use another --out");
      }
    }

    experiments::AblationSettings set;
    set.views = o.views;
    set.initial_views = o.initial_views;
    set.protocol = protocol;
    set.cluster_min_logodds = o.cluster_min_logodds >= 0.0 ? o.cluster_min_logodds
                              : protocol == experiments::AblationProtocol::kPaper ? 0.5
                                                                              : -1.0;
    set.seed = o.seed;
    std::vector<nlohmann::json> results(jobs.size());
    auto job_path = [&](const Job& j) {
      return out + "/jobs/" + configs[j.config].id() + "/trial" + std::to_string(j.trial) + "_plant" +
             std::to_string(j.plant) + ".json";
    };
    std::size_t reused = 0;
    if (reuse)
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        std::ifstream f(job_path(jobs[i]));
        if (!f) continue;
        try {
          nlohmann::json j = nlohmann::json::parse(f);
          if (j["steps"].size() == std::size_t(o.views)) {
            results[i] = std::move(j);
            ++reused;
          }
        } catch (const std::exception&) {
        }
      }
    if (o.summarize_only && reused == 0)
      throw InputError("--summarize-only: no finished jobs with these settings in '" + o.out + "'");
    write_json_atomic(out + "/settings.json", settings);
    out_dir.make_subdir("trials");
    for (const auto& c : configs) out_dir.make_subdir("jobs/" + c.id());
    // Never more workers (each with its own Simulator and Renderer) than jobs to run.
    const int workers = o.summarize_only ? 0 : static_cast<int>(std::min<std::size_t>(o.threads, jobs.size() - reused));
    spdlog::info("ablation: {} configurations x {} trials x {} plants = {} jobs ({} reused), {} views each, {} workers",
                 configs.size(), o.trials, o.plants, jobs.size(), reused, o.views, workers);

    std::atomic<std::size_t> next{0}, done{reused};
    std::mutex log_mutex;
    std::exception_ptr failure;
    const auto t0 = Clock::now();
    auto worker = [&] {
      try {
        sim::Simulator sim(world, default_robot_config());
        sim::Renderer renderer(sim, spec.camera);
        for (;;) {
          const std::size_t i = next++;
          if (i >= jobs.size()) break;
          if (!results[i].is_null()) continue;
          const Job& j = jobs[i];
          const auto tj = Clock::now();
          nlohmann::json r =
              experiments::run_ablation_job(configs[j.config], j.trial, j.plant, set, bundle, world, renderer);
          write_json_atomic(job_path(j), r);
          const double cov = r["steps"].back()["coverage"].get<double>();
          results[i] = std::move(r);
          const std::size_t d = ++done;
          std::lock_guard<std::mutex> lock(log_mutex);
          const double el = seconds_since(t0);
          const double eta = d > reused ? el / double(d - reused) * double(jobs.size() - d) : 0.0;
          std::fprintf(stderr, "[%zu/%zu] %s trial %d plant %d: coverage %.3f after %d views (%.1f s; elapsed %.0f s, eta %.0f s)\n",
                       d, jobs.size(), configs[j.config].id().c_str(), j.trial, j.plant, cov, o.views,
                       seconds_since(tj), el, eta);
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(log_mutex);
        if (!failure) failure = std::current_exception();
        next = jobs.size();
      }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < workers; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);

    print_table(experiments::summarize_ablation(out, configs, o.plants, o.views, results, jobs, o.coverage_target), o.views);
    if (!o.no_plots) {
      const std::string script = find_data_file("tools/plot_ablation.py");
      const ProcessStatus plot = run_process({"/usr/bin/python3", script, out});
      if (!plot.ok()) spdlog::warn("plots failed (needs python3-matplotlib): {} {}: {}", script, out, plot.describe());
    }
    out_dir.commit();
    std::printf("ablation done in %.0f s; wrote %s (summary.csv, table.csv, trials/, jobs/, *.png)\n", seconds_since(t0),
                o.out.c_str());
  });
}

}  // namespace canopy::cli
