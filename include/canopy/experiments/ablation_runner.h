#pragma once
// Running the free-camera ablation (ablation.h): the configuration matrix, the jobs
// (trial-major, so an interrupted run has whole trials), worker threads with one Simulator and
// Renderer each, every finished job written at once (jobs/<config>/trial<t>_plant<p>.json),
// resuming a run with the same settings, and the summary (trials/, summary.csv, table.csv).
// A job's result depends only on its seeds, not on the thread or the order of the jobs.

#include <functional>
#include <string>
#include <vector>

#include "canopy/common/output_dir.h"
#include "canopy/experiments/ablation.h"

namespace canopy::experiments {

/// A setting swept over several values ("mapping.map.ray_range_m" over "0.8", "3.0").
struct SettingSweep {
  std::string key;
  std::vector<std::string> values;
};

/// The paper's matrix: every gain with the main ray set ("ours" when given, else the first),
/// OSAMCEP (or the first gain) with every other ray set; OSAMCEP once per proximity test in
/// `osamcep_proximities` ("" = the bundle's own); each of those once per combination of the
/// sweeps' values; all of it at every P_gt. Repeated names are dropped.
std::vector<AblationConfig> ablation_matrix(const std::vector<std::string>& gains, const std::vector<std::string>& rays,
                                            const std::vector<double>& p_gt,
                                            const std::vector<std::string>& osamcep_proximities,
                                            const std::vector<SettingSweep>& sweeps = {});

/// What a run does.
struct AblationPlan {
  std::vector<AblationConfig> configs;
  int trials = 10;
  int plants = 6;
  AblationSettings settings;
  std::string world_name;  ///< Recorded in settings.yaml (resume compares it).
};

/// How it runs.
struct AblationRunOptions {
  int threads = 2;
  bool resume = false;           ///< Reuse finished jobs of a run with the same settings.
  bool summarize_only = false;   ///< Run nothing; summarize the finished jobs.
  double coverage_target = 0.8;  ///< For the views-to-target table.
  std::function<void(const std::string& line)> progress;
  std::function<bool()> stop_requested;  ///< Polled before each job; true: no further job starts.
};

/// What it did.
struct AblationRunResult {
  std::vector<AblationRow> rows;
  std::size_t jobs = 0, reused = 0;
  bool interrupted = false;  ///< stop_requested ended the run; the finished jobs are written.
  double seconds = 0.0;
};

/// The run's record (run.yaml in the output folder): the plan; the bundle goes to settings.yaml.
YAML::Node ablation_run_record(const AblationPlan& plan);

/// Runs `plan` into `out` (run.yaml, settings.yaml, jobs/, trials/, summary.csv, table.csv);
/// the caller commits `out`. With options.resume, finished jobs in `out` are reused when the
/// folder's run.yaml and settings.yaml equal this run's (else InputError). Throws the first
/// job's failure.
AblationRunResult run_ablation(const AblationPlan& plan, const settings::Settings& bundle, const world::World& world,
                               const StagedDir& out, const AblationRunOptions& options);

}  // namespace canopy::experiments
