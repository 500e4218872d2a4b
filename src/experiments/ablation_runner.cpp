#include "canopy/experiments/ablation_runner.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/common/timer.h"
#include "canopy/common/value_text.h"
#include "canopy/sim/simulator.h"

namespace canopy::experiments {

namespace {

// Every combination of the sweeps' values, as override lists (one empty list without sweeps).
std::vector<std::vector<settings::SettingOverride>> sweep_combinations(const std::vector<SettingSweep>& sweeps) {
  std::vector<std::vector<settings::SettingOverride>> out = {{}};
  for (const SettingSweep& s : sweeps) {
    std::vector<std::vector<settings::SettingOverride>> next;
    for (const auto& prefix : out)
      for (const std::string& v : s.values) {
        auto o = prefix;
        o.emplace_back(s.key, v);
        next.push_back(std::move(o));
      }
    out = std::move(next);
  }
  return out;
}

}  // namespace

std::vector<AblationConfig> ablation_matrix(const std::vector<std::string>& gains, const std::vector<std::string>& rays,
                                            const std::vector<double>& p_gt,
                                            const std::vector<std::string>& osamcep_proximities,
                                            const std::vector<SettingSweep>& sweeps) {
  const std::string main_rays = std::find(rays.begin(), rays.end(), "ours") != rays.end() ? "ours" : rays.at(0);
  const std::string main_gain =
      std::find(gains.begin(), gains.end(), "osamcep") != gains.end() ? "osamcep" : gains.at(0);
  const std::vector<std::string> proximities = osamcep_proximities.empty() ? std::vector<std::string>{""}
                                                                           : osamcep_proximities;
  const auto combos = sweep_combinations(sweeps);
  // OSAMCEP runs once per proximity test asked for, each once per sweep combination.
  auto variants = [&](const std::string& gain) {
    std::vector<std::vector<settings::SettingOverride>> out;
    for (const std::string& p : gain == "osamcep" ? proximities : std::vector<std::string>{""})
      for (const auto& combo : combos) {
        std::vector<settings::SettingOverride> o;
        if (!p.empty()) o.emplace_back("nbv.gain.proximity", p);
        o.insert(o.end(), combo.begin(), combo.end());
        out.push_back(std::move(o));
      }
    return out;
  };
  std::vector<AblationConfig> configs;
  for (double p : p_gt) {
    for (const auto& g : gains)
      for (const auto& o : variants(g)) configs.push_back({g, main_rays, p, o});
    for (const auto& r : rays)
      if (r != main_rays)
        for (const auto& o : variants(main_gain)) configs.push_back({main_gain, r, p, o});
  }
  return configs;
}

YAML::Node ablation_run_record(const AblationPlan& plan) {
  YAML::Node n;
  n["world"] = plan.world_name;
  n["plants"] = plan.plants;
  n["trials"] = plan.trials;
  n["views"] = plan.settings.views;
  n["initial_views"] = plan.settings.initial_views;
  n["protocol"] = to_string(plan.settings.protocol);
  n["cluster_min_logodds"] = plan.settings.cluster_min_logodds;
  n["seed"] = plan.settings.seed;
  YAML::Node configs(YAML::NodeType::Sequence);
  for (const AblationConfig& c : plan.configs) configs.push_back(c.id());
  n["configurations"] = configs;
  return n;
}

AblationRunResult run_ablation(const AblationPlan& plan, const settings::Settings& bundle, const world::World& world,
                               const StagedDir& out_dir, const AblationRunOptions& options) {
  const Stopwatch watch;
  const std::string out = out_dir.working_dir();
  auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  std::vector<AblationJobId> jobs;  // trial-major, so an interrupted run has whole trials
  for (int t = 0; t < plan.trials; ++t)
    for (std::size_t c = 0; c < plan.configs.size(); ++c)
      for (int p = 0; p < plan.plants; ++p) jobs.push_back({c, t, p});

  const std::string record = yaml_text(ablation_run_record(plan));
  const std::string settings = bundle.to_yaml_text();
  const bool reuse = options.resume || options.summarize_only;
  if (reuse) {
    // Finished jobs are only reused from a run with the same plan and settings.
    for (const auto& [file, expected] : {std::pair<std::string, std::string>{"run.yaml", record}, {"settings.yaml", settings}}) {
      std::ifstream previous(out + "/" + file);
      if (!previous) continue;
      const std::string text((std::istreambuf_iterator<char>(previous)), std::istreambuf_iterator<char>());
      if (text != expected)
        throw InputError("--resume: " + file + " differs from that of the run in " + out_dir.final_dir() +
                         " (world, plants, views, trials, seed, configurations or the settings bundle); use another --out");
    }
  }
  std::vector<nlohmann::json> results(jobs.size());
  auto job_path = [&](const AblationJobId& j) {
    return out + "/jobs/" + plan.configs[j.config].id() + "/trial" + std::to_string(j.trial) + "_plant" +
           std::to_string(j.plant) + ".json";
  };
  std::size_t reused = 0;
  if (reuse)
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      std::ifstream f(job_path(jobs[i]));
      if (!f) continue;
      try {
        nlohmann::json j = nlohmann::json::parse(f);
        if (j["steps"].size() == std::size_t(plan.settings.views)) {
          results[i] = std::move(j);
          ++reused;
        }
      } catch (const std::exception&) {
      }
    }
  if (options.summarize_only && reused == 0)
    throw InputError("--summarize-only: no finished jobs with these settings in '" + out_dir.final_dir() + "'");
  write_file_atomic(out + "/run.yaml", record);
  write_file_atomic(out + "/settings.yaml", settings);
  out_dir.make_subdir("trials");
  for (const auto& c : plan.configs) out_dir.make_subdir("jobs/" + c.id());
  // Never more workers (each with its own Simulator and Renderer) than jobs to run.
  const int workers =
      options.summarize_only ? 0 : static_cast<int>(std::min<std::size_t>(std::size_t(options.threads), jobs.size() - reused));
  char head[200];
  c_snprintf(head, sizeof head, "ablation: %zu configurations x %d trials x %d plants = %zu jobs (%zu reused), %d views each, %d workers",
                plan.configs.size(), plan.trials, plan.plants, jobs.size(), reused, plan.settings.views, workers);
  progress(head);

  std::atomic<std::size_t> next{0}, done{reused};
  std::atomic<bool> stopped{false};
  std::mutex log_mutex;
  std::exception_ptr failure;
  auto worker = [&] {
    try {
      sim::Simulator sim(world, default_robot_config());
      sim::Renderer renderer(sim, world.spec.camera);
      for (;;) {
        if (options.stop_requested && options.stop_requested()) {
          stopped = true;
          break;
        }
        const std::size_t i = next++;
        if (i >= jobs.size()) break;
        if (!results[i].is_null()) continue;
        const AblationJobId& j = jobs[i];
        const Stopwatch job_watch;
        nlohmann::json r = run_ablation_job(plan.configs[j.config], j.trial, j.plant, plan.settings, bundle, world, renderer);
        write_json_atomic(job_path(j), r);
        const double cov = r["steps"].back()["coverage"].get<double>();
        results[i] = std::move(r);
        const std::size_t d = ++done;
        std::lock_guard<std::mutex> lock(log_mutex);
        const double el = watch.seconds();
        const double eta = d > reused ? el / double(d - reused) * double(jobs.size() - d) : 0.0;
        char line[300];
        c_snprintf(line, sizeof line,
                      "[%zu/%zu] %s trial %d plant %d: coverage %.3f after %d views (%.1f s; elapsed %.0f s, eta %.0f s)", d,
                      jobs.size(), plan.configs[j.config].id().c_str(), j.trial, j.plant, cov, plan.settings.views,
                      job_watch.seconds(), el, eta);
        progress(line);
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

  AblationRunResult result;
  result.rows = summarize_ablation(out, plan.configs, plan.plants, plan.settings.views, results, jobs,
                                   options.coverage_target);
  result.jobs = jobs.size();
  result.reused = reused;
  result.interrupted = stopped.load() && done.load() < jobs.size();
  result.seconds = watch.seconds();
  return result;
}

}  // namespace canopy::experiments
