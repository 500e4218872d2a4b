#pragma once
// Experiments: a sweep of missions over methods x segmentation noise P_gt x seeds (the paper's
// Fig. 3 and 4: 3 methods x P_gt {1.0, 0.7} x 10 seeds = 60 missions), optionally over world
// seeds too. An experiment file (experiments/*.yaml, strict keys) names a world, a settings
// bundle with overrides, the methods, the P_gt values, the seeds and optionally the world
// seeds. Each (method, P_gt, world seed, seed) is a trial, one mission, with a stable id made
// of those ("ours_pgt0.7_seed3", or "ours_pgt0.7_world101_seed3" with world seeds): with world
// seeds, each trial's procedural plants are generated from the world file with its world seed
// (imported plants stay as placed), so an experiment spans many worlds.
//
// An experiment folder holds experiment.json (the experiment's name and trial list, which
// `canopy report` uses to list missing trials) and trials/<id>/, one folder per finished
// trial, published by a rename so that it is either complete or absent:
//   trials/<id>/trial.json    the trial's identity (method, P_gt, seed, world, settings),
//                             status ok|failed, the failure message, wall time, runner;
//   trials/<id>/world.yaml, settings.yaml   what the mission was given;
//   trials/<id>/mission/      the mission's own folder (views.csv, timing.csv, summary.json, ...);
//   trials/<id>/log.txt       the mission's standard output and error.
// A trial runs as a child process (`canopy mission`) with a timeout, so a crash or a hang is
// recorded as that trial's failure and the sweep goes on. Trials in flight live in
// trials/<id>.partial/ and are ignored by the report.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/settings/settings.h"
#include "canopy/world/world_spec.h"

namespace canopy::experiments {

/// One method of an experiment: a view planner by name with its gain and ray set (the
/// bundle's `method` section), and any settings of its own by key (`set:` in the file).
struct ExperimentMethod {
  std::string label;             ///< Name in trial ids and plots; unique; [A-Za-z0-9-]+.
  nbv::MethodChoice choice;
  std::vector<settings::SettingOverride> set;
};

/// One mission of an experiment.
struct TrialSpec {
  std::string id;                ///< "<label>_pgt<P_gt>[_world<world seed>]_seed<seed>", stable.
  ExperimentMethod method;
  double p_gt = 1.0;
  std::uint64_t seed = 1;
  /// The seed the trial's world is generated with; absent: the world file's own seed.
  std::optional<std::uint64_t> world_seed;
  nlohmann::json to_json() const;  ///< {id, label, method, gain, rays, p_gt, seed[, world_seed]}.
  static TrialSpec from_json(const nlohmann::json& j, const std::string& where);
};

/// The id of a (method label, P_gt, seed[, world seed]): P_gt printed with up to 6 significant
/// digits; "<label>_pgt<P_gt>_seed<seed>", or "<label>_pgt<P_gt>_world<world seed>_seed<seed>".
std::string trial_id(const std::string& label, double p_gt, std::uint64_t seed,
                     std::optional<std::uint64_t> world_seed = std::nullopt);

/// Largest world seed an experiment may name (a world file's seed is a non-negative 63-bit integer).
constexpr std::uint64_t kMaxWorldSeed = 9223372036854775807ULL;

/// Zstandard level of a compact trial's files: a default mission's 17 MB map.csm in about
/// 0.7 MB and 0.5 s, its 1.9 MB report.html in 0.4 MB (level 19: 0.48 MB, but 13 s).
constexpr int kTrialZstdLevel = 12;

/// Compacts a finished mission folder: map.csm and report.html become map.csm.zst and
/// report.html.zst (each checked to read back as the very bytes before the original goes),
/// map.ply and map.bt are removed (mapping::load_map reads the compressed map; its export_ply
/// and export_bt write them again). Returns the files removed and written, as names.
std::vector<std::string> compact_trial_files(const std::string& mission_dir);
/// The report page of a compact trial's mission folder, report.html, unpacked from
/// report.html.zst when it is not there (what `canopy report` links). Returns false when the
/// folder has neither.
bool unpack_trial_page(const std::string& mission_dir);

/// A parsed experiment file.
struct Experiment {
  std::string name;
  std::string source_file;
  std::string world_file;        ///< Resolved path of the world file.
  world::WorldSpec world;
  settings::Settings settings;             ///< The bundle with the file's overrides (P_gt set per trial).
  std::vector<ExperimentMethod> methods;
  std::vector<double> p_gt;
  std::vector<std::uint64_t> seeds;
  /// World seeds (`world_seeds:`, a list or {first, count}); empty: every trial runs on the
  /// world file's own world.
  std::vector<std::uint64_t> world_seeds;
  double trial_timeout_s = 3600.0;  ///< Wall time after which a trial is killed and failed.
  /// `trial_files`: "compact" (the default) keeps a finished trial's map and report page in
  /// Zstandard frames that read back byte-identical (mission/map.csm.zst, report.html.zst) and
  /// drops map.ply and map.bt, which the map rebuilds (compact_trial_files); "full" keeps the
  /// mission's files as it wrote them.
  bool compact_trials = true;

  /// Loads an experiment file. Relative paths (world, settings) are read from the file's
  /// folder first, then from the source tree. Throws InputError naming file, key and value
  /// for unknown keys, repeated labels or values, unknown methods, gains or ray sets, P_gt
  /// outside [0, 1], bad overrides, ...
  static Experiment load(const std::string& path, const RobotConfig& robot);
  /// The same from text; `name` stands in for the file and relative paths are read from `dir`.
  static Experiment load_string(const std::string& text, const std::string& name, const std::string& dir,
                                const RobotConfig& robot);

  /// Every trial, world-seed-major then seed-major (world seed, seed, P_gt, method), so any
  /// prefix or shard holds a mix of methods.
  std::vector<TrialSpec> trials() const;
  /// The world of a trial: the experiment's world, with the trial's world seed if it has one
  /// (procedural plants change with it; imported plants stay as placed).
  world::WorldSpec trial_world(const TrialSpec& trial) const;
  /// The settings bundle of a trial (the experiment's, with the trial's P_gt).
  settings::Settings trial_settings(const TrialSpec& trial) const;
  /// What identifies a trial's results: its spec, the resolved world and the whole settings
  /// bundle (saved in trial.json; --resume compares it).
  nlohmann::json trial_identity(const TrialSpec& trial) const;
  /// experiment.json: {"name", "trials": [TrialSpec...]}.
  nlohmann::json manifest() const;
};

/// Most shards an experiment may be split into.
constexpr std::uint64_t kMaxShards = 1000000;
/// Parses "i/n" (0 <= i < n <= kMaxShards, decimal digits only); throws InputError naming `option`.
std::pair<int, int> parse_shard(const std::string& text, const std::string& option = "--shard");
/// Trials of shard i of n: the k-th trial of `trials` belongs to shard k mod n, so the n
/// shards are disjoint and together hold every trial once.
std::vector<TrialSpec> shard_trials(const std::vector<TrialSpec>& trials, int index, int count);

/// The first setting in which two trial identities differ, as "path: 'a' vs 'b'"
/// (e.g. "settings.mission.loop.views_per_stop: '12' vs '2'"); "" when equal.
std::string first_difference(const nlohmann::json& saved, const nlohmann::json& expected);

/// How run_experiment runs trials.
struct ExperimentRunOptions {
  std::vector<std::string> mission_command;  ///< The program and leading arguments of a mission: {canopy, "mission"}.
  int jobs = 1;                  ///< Trials at once (child processes).
  int shard_index = 0, shard_count = 1;
  bool resume = false;           ///< Add to an existing experiment folder, skipping complete trials.
  std::string runner;            ///< Free text saved in trial.json (host, SLURM job), not compared.
  std::function<void(const std::string& line)> progress;
  std::function<bool()> stop_requested;  ///< Polled; true kills running trials (left .partial) and starts no more.
};

/// What a run did.
struct ExperimentRunSummary {
  int total = 0;                 ///< Trials of the experiment.
  int in_shard = 0;              ///< Trials of this shard.
  int skipped = 0;               ///< Complete already (resume).
  int ok = 0, failed = 0;        ///< Run now.
  int busy = 0;                  ///< Skipped: another process runs them now (their trials/<id>.lock is held).
  bool interrupted = false;      ///< Stopped by stop_requested; the unfinished trials are left .partial.
  double wall_time_s = 0.0;
};

/// Runs this shard's trials into `out_dir` (see the file comment). Without `resume`, `out_dir`
/// must not hold an experiment yet; with it, the folder's experiment.json must list the same
/// trials and every complete trial's saved identity must equal the experiment's (else
/// InputError naming the trial and the first differing setting); failed trials and .partial
/// folders are run again. Several shards may run into one folder at once (a shared
/// filesystem): each trial is written only by its own shard.
ExperimentRunSummary run_experiment(const Experiment& experiment, const std::string& out_dir,
                                    const ExperimentRunOptions& options);

}  // namespace canopy::experiments
