// canopy ablate: the paper's ablation (Fig. 5 and 6) with a free-moving camera (no arm).
// For each configuration (a gain with our ray set, or OSAMCEP with another ray set; each at
// every P_gt), trial and plant: start an empty map from a seeded initial view set, then
// repeatedly cluster the fruit voxels near the plant, score the candidate views around the
// clusters, render the best one with the free camera and insert it; after every view record
// the plant's fruit entropy and surface coverage and the step's ray-casting time.
//
// Rules of a job: the map starts empty; `--initial-views` random views around the plant (the
// same for every configuration of a trial) come first; then each step clusters the target
// voxels in a box of +-0.25 m around the plant's axis, scores the candidates of every cluster,
// and takes the best one that was not taken before; when the planner has no view (no
// clusters, every cluster done) a random view around the plant is taken and the reason is
// recorded. Coverage and entropy are the plant's fruits' (paper Experiments metrics); the
// ray-casting time of a step is the sum over its candidates, and per view = that / candidates.
//
// Jobs (configuration, trial, plant) run on worker threads, each with its own Simulator and
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
#include "canopy/mapping/scan_inserter.h"
#include "canopy/nbv/planner.h"
#include "canopy/sim/renderer.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct AblationConfig {
  std::string gain, rays;
  double pgt = 1.0;
  std::string id() const {
    char b[64];
    std::snprintf(b, sizeof b, "%s_%s_pgt%.2f", gain.c_str(), rays.c_str(), pgt);
    return b;
  }
};

struct Job {
  std::size_t config = 0;
  int trial = 0;
  int plant = 0;
};

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

// A view around the plant's axis: azimuth uniform, height in the plant's fruit zone.
Pose random_plant_view(const world::World& world, int plant, double radius_m, Rng& rng) {
  const world::Plant& p = world.plants[static_cast<std::size_t>(plant)];
  const double a = rng.uniform(0.0, 2.0 * M_PI);
  const double h = p.height_m * rng.uniform(world.spec.plant.fruit_zone_min, world.spec.plant.fruit_zone_max);
  const Vec3 target = p.base_position + Vec3(0, 0, h);
  return look_at(target + radius_m * Vec3(std::cos(a), std::sin(a), 0.0), target);
}

struct Settings {
  int views = 30;
  int initial_views = 2;
  double plant_radius_m = 0.25;
  double view_radius_m = 0.45;
  double min_view_separation_m = 0.01;
  std::uint64_t seed = 1;
};

// One (configuration, trial, plant) run; deterministic in its seeds.
nlohmann::json run_job(const AblationConfig& cfg, int trial, int plant, const Settings& set,
                       const mapping::MappingConfig& mcfg, const nbv::NbvParams& np, const world::World& world,
                       sim::Renderer& renderer) {
  const std::uint64_t job_seed = mix_seed(set.seed, std::uint64_t(trial) * 1000 + std::uint64_t(plant));
  perception::ExtractorParams ep = mcfg.extractor;
  ep.p_gt = cfg.pgt;
  ep.seed = mix_seed(job_seed, 1);  // same noise stream for every configuration (paired trials)
  perception::SemanticExtractor extractor(ep, world.spec.classes);
  mapping::SemanticMapParams mp = mcfg.map;
  mp.threads = 1;  // jobs run in parallel instead
  mapping::SemanticOcTree map(mp, world.spec.classes);
  mapping::ScanInserter inserter(map);
  nbv::VoxelIndex index;
  const auto gain = nbv::make_gain(cfg.gain, np.gain);
  const nbv::RaySetEntry& rays = nbv::ray_set(cfg.rays);
  nbv::ClusterPlanner planner(np, renderer.intrinsics());
  Rng init_rng(mix_seed(job_seed, 2));      // initial views: shared by all configurations
  Rng fallback_rng(mix_seed(job_seed, 3));  // views when the planner has none

  world::GroundTruth truth;
  for (const world::FruitTruth* f : world.truth.fruits_of_plant(plant)) truth.fruits.push_back(*f);
  const world::Plant& pl = world.plants[static_cast<std::size_t>(plant)];
  const Eigen::AlignedBox3d region(pl.base_position - Vec3(set.plant_radius_m, set.plant_radius_m, 0.0),
                                   pl.base_position + Vec3(set.plant_radius_m, set.plant_radius_m, pl.height_m + 0.1));

  // A view is never taken twice: candidates within min_view_separation_m of a taken view are
  // dropped (otherwise gains that trust carved free space keep re-taking one view).
  std::vector<Vec3> taken;
  const nbv::CandidateFilter not_taken = [&](const nbv::Candidate& c) {
    for (const Vec3& p : taken)
      if ((p - c.T_world_camera.translation()).norm() < set.min_view_separation_m) return false;
    return true;
  };
  nlohmann::json steps = nlohmann::json::array();
  for (int v = 0; v < set.views; ++v) {
    nlohmann::json step = {{"view", v + 1}};
    Pose T;
    if (v < set.initial_views) {
      T = random_plant_view(world, plant, set.view_radius_m, init_rng);
      step["source"] = "initial";
    } else {
      index.refresh(map);
      const auto clusters = nbv::find_clusters(map, np.cluster, &region);
      const nbv::Plan plan =
          planner.plan(index, clusters, *gain, rays, mix_seed(job_seed, 100 + std::uint64_t(v)), not_taken);
      step["clusters"] = clusters.size();
      step["candidates"] = plan.candidates;
      step["ms_raycast_step"] = plan.ms_raycast;
      step["ms_raycast_per_view"] = plan.candidates ? plan.ms_raycast / double(plan.candidates) : 0.0;
      step["ms_index_build"] = index.build_ms();
      if (!plan.views.empty()) {
        T = plan.views.front().candidate.T_world_camera;
        step["source"] = "nbv";
        step["gain"] = plan.views.front().score.gain;
        step["rays"] = plan.views.front().score.rays;
      } else {
        T = random_plant_view(world, plant, set.view_radius_m, fallback_rng);
        step["source"] = "fallback";
        step["reason"] = plan.reason;
      }
    }
    taken.push_back(T.translation());
    const LabelledFrame frame = renderer.render_free_camera(T);  // the renderer serialises draws
    inserter.insert(extractor.extract(frame));
    const mapping::MapMetrics m = mapping::evaluate_map(map, truth, mcfg.metrics);
    step["pose"] = pose_to_json(T);
    step["coverage"] = m.coverage;
    step["entropy"] = m.total_entropy;
    steps.push_back(step);
  }
  return {{"config", cfg.id()}, {"gain", cfg.gain},   {"rays", cfg.rays}, {"p_gt", cfg.pgt},
          {"trial", trial},     {"plant", plant},     {"seed", job_seed}, {"fruits", truth.fruits.size()},
          {"steps", steps}};
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}
double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size() - 1));
}

// Writes per-trial JSONs, summary.csv and table.csv; prints the table.
void summarize(const std::string& out, const std::vector<AblationConfig>& configs, int plants, int views,
               const std::vector<nlohmann::json>& results, const std::vector<Job>& jobs, double target_coverage) {
  std::ofstream csv(out + "/summary.csv.tmp");
  csv << "config,gain,rays,p_gt,view,trials,coverage_mean,coverage_std,entropy_mean,entropy_std\n";
  std::ofstream table(out + "/table.csv.tmp");
  table << "config,gain,rays,p_gt,trials,views_to_target_mean_curve,views_to_target_per_plant_mean,"
           "plant_runs_reaching_target,plant_runs,raycast_ms_per_view_mean,final_coverage_mean,final_entropy_mean\n";
  std::printf("\n%-28s %6s %14s %16s %10s %13s %10s\n", "configuration", "trials", "views->cov80", "per-plant mean",
              "reached", "raycast ms/v", "final cov");
  for (std::size_t c = 0; c < configs.size(); ++c) {
    // coverage[trial][plant][view]
    std::map<int, std::map<int, const nlohmann::json*>> by_trial;
    for (std::size_t j = 0; j < jobs.size(); ++j)
      if (jobs[j].config == c && !results[j].is_null()) by_trial[jobs[j].trial][jobs[j].plant] = &results[j];
    std::vector<int> complete;  // trials with every plant done
    for (const auto& [t, ps] : by_trial)
      if (int(ps.size()) == plants) complete.push_back(t);
    for (int t : complete) {
      nlohmann::json tj = {{"config", configs[c].id()}, {"trial", t}, {"plants", nlohmann::json::array()}};
      for (const auto& [p, r] : by_trial[t]) tj["plants"].push_back(*r);
      write_json_atomic(out + "/trials/" + configs[c].id() + "_trial" + std::to_string(t) + ".json", tj);
    }
    if (complete.empty()) continue;
    std::vector<double> mean_cov_curve(static_cast<std::size_t>(views), 0.0);
    std::vector<double> reach_views, ray_ms, final_cov, final_ent;
    int runs = 0;
    for (int v = 0; v < views; ++v) {
      std::vector<double> cov_t, ent_t;
      for (int t : complete) {
        std::vector<double> cov_p, ent_p;
        for (const auto& [p, r] : by_trial[t]) {
          cov_p.push_back((*r)["steps"][v]["coverage"].get<double>());
          ent_p.push_back((*r)["steps"][v]["entropy"].get<double>());
        }
        cov_t.push_back(mean(cov_p));
        ent_t.push_back(mean(ent_p));
      }
      mean_cov_curve[std::size_t(v)] = mean(cov_t);
      csv << configs[c].id() << "," << configs[c].gain << "," << configs[c].rays << "," << configs[c].pgt << ","
          << v + 1 << "," << complete.size() << "," << mean(cov_t) << "," << stddev(cov_t) << "," << mean(ent_t)
          << "," << stddev(ent_t) << "\n";
      if (v == views - 1) {
        final_cov = cov_t;
        final_ent = ent_t;
      }
    }
    for (int t : complete)
      for (const auto& [p, r] : by_trial[t]) {
        ++runs;
        for (const auto& s : (*r)["steps"]) {
          if (s.contains("ms_raycast_per_view") && s.value("candidates", 0) > 0)
            ray_ms.push_back(s["ms_raycast_per_view"].get<double>());
        }
        for (const auto& s : (*r)["steps"])
          if (s["coverage"].get<double>() >= target_coverage) {
            reach_views.push_back(s["view"].get<double>());
            break;
          }
      }
    int curve_views = -1;
    for (int v = 0; v < views; ++v)
      if (mean_cov_curve[std::size_t(v)] >= target_coverage) {
        curve_views = v + 1;
        break;
      }
    table << configs[c].id() << "," << configs[c].gain << "," << configs[c].rays << "," << configs[c].pgt << ","
          << complete.size() << "," << curve_views << "," << mean(reach_views) << "," << reach_views.size() << ","
          << runs << "," << mean(ray_ms) << "," << mean(final_cov) << "," << mean(final_ent) << "\n";
    char reach[32];
    if (curve_views > 0) std::snprintf(reach, sizeof reach, "%d", curve_views);
    else std::snprintf(reach, sizeof reach, ">%d", views);
    std::printf("%-28s %6zu %14s %16.1f %5zu/%-4d %13.4f %10.3f\n", configs[c].id().c_str(), complete.size(), reach,
                mean(reach_views), reach_views.size(), runs, mean(ray_ms), mean(final_cov));
  }
  csv.close();
  table.close();
  std::filesystem::rename(out + "/summary.csv.tmp", out + "/summary.csv");
  std::filesystem::rename(out + "/table.csv.tmp", out + "/table.csv");
}

}  // namespace

void add_ablate_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string config = find_data_file("configs/mapping.yaml");
    std::string nbv_config = find_data_file("configs/nbv.yaml");
    int plants = 6, views = 30, trials = 10, initial_views = 2, threads = 2;
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
  sub->add_option("--config", opt->config, "Mapping config (YAML)")->capture_default_str();
  sub->add_option("--nbv-config", opt->nbv_config, "Next-best-view config (YAML)")->capture_default_str();
  sub->add_option("--plants", opt->plants, "Plants (the first N of the world)")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--views", opt->views, "Views per plant, initial ones included")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--trials", opt->trials, "Trials (seeded initial views)")->capture_default_str()->check(CLI::Range(1, 1000));
  sub->add_option("--initial-views", opt->initial_views, "Random initial views per plant")->capture_default_str()->check(CLI::Range(1, 1000));
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
    mapping::MappingConfig mcfg = mapping::MappingConfig::load(o.config);
    if (!o.seg.empty()) mcfg.extractor.source = perception::label_source_from_string(o.seg, "--seg");
    const nbv::NbvParams np = nbv::NbvParams::load(o.nbv_config);
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
    for (double p : pgts) {
      for (const auto& g : gains) configs.push_back({g, main_rays, p});
      for (const auto& r : rays)
        if (r != main_rays) configs.push_back({main_gain, r, p});
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

    Settings set;
    set.views = o.views;
    set.initial_views = o.initial_views;
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
          nlohmann::json r = run_job(configs[j.config], j.trial, j.plant, set, mcfg, np, world, renderer);
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

    summarize(out, configs, o.plants, o.views, results, jobs, o.coverage_target);
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
