// canopy experiment: runs an experiment file's trials (methods x P_gt x seeds), one child
// `canopy mission` per trial, N at once, optionally one shard of n (SLURM array tasks, GNU
// parallel jobs). The rules (folder layout, resume checks, failures) are in
// canopy/experiments/experiment.h.

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/experiments/experiment.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {


// Host, pid and the SLURM job, for trial.json (provenance only).
std::string runner_text() {
  char host[256] = {0};
  ::gethostname(host, sizeof host - 1);
  std::string s = std::string("host ") + host + ", pid " + std::to_string(::getpid());
  if (const char* job = std::getenv("SLURM_JOB_ID")) s += std::string(", SLURM job ") + job;
  if (const char* task = std::getenv("SLURM_ARRAY_TASK_ID")) s += std::string(", array task ") + task;
  return s;
}

}  // namespace

void add_experiment_command(CLI::App& app) {
  struct Options {
    std::string config, out, shard = "0/1";
    int jobs = 1;
    bool resume = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("experiment", "Run an experiment file's trials (methods x P_gt x seeds), each a mission");
  sub->add_option("--config", o->config, "Experiment file (experiments/*.yaml)")->required();
  sub->add_option("--out", o->out, "Experiment folder (trials/<id>/ per trial)")->required();
  sub->add_option("--jobs", o->jobs, "Trials at once on this machine")->capture_default_str()->check(CLI::Range(1, 256));
  sub->add_option("--shard", o->shard, "Run shard i of n (0 <= i < n): trial k belongs to shard k mod n")->capture_default_str();
  sub->add_flag("--resume", o->resume, "Continue the experiment in --out: skip complete trials, run the rest");
  sub->callback([o] {
    const auto [index, count] = experiments::parse_shard(o->shard);
    const experiments::Experiment e = experiments::Experiment::load(o->config, default_robot_config());
    jobs::load_world_spec(e.world_file);  // the mission's own checks (the robot fits the aisle), before any trial
    experiments::ExperimentRunOptions ro;
    ro.mission_command = {std::filesystem::read_symlink("/proc/self/exe").string(), "mission"};
    ro.jobs = o->jobs;
    ro.shard_index = index;
    ro.shard_count = count;
    ro.resume = o->resume;
    ro.runner = runner_text();
    ro.progress = [](const std::string& line) { spdlog::info("{}", line); };
    ro.stop_requested = [] { return interrupt_requested(); };
    const InterruptScope interrupts;  // Ctrl-C / SIGTERM (scancel): running trials stop, left .partial
    const experiments::ExperimentRunSummary s = experiments::run_experiment(e, o->out, ro);
    spdlog::info("experiment {} shard {}: {} trials ran ({} ok, {} failed), {} complete already, {:.0f} s; results in {}/trials/",
                 e.name, o->shard, s.ok + s.failed, s.ok, s.failed, s.skipped, s.wall_time_s, o->out);
    if (s.interrupted) throw Interrupted("interrupted; the unfinished trials are left .partial, --resume runs them");
    if (s.busy > 0)
      throw InputError(std::to_string(s.busy) + " trial(s) of " + o->out +
                       " are being run by another canopy experiment now and were skipped; --resume when it has finished");
    if (s.failed > 0)
      throw std::runtime_error(std::to_string(s.failed) + " of " + std::to_string(s.ok + s.failed) +
                               " trials failed (their trial.json and log.txt say why); --resume runs them again");
  });
}

}  // namespace canopy::cli
