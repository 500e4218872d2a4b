#pragma once
// `canopy report`: merges the trial folders of any number of experiment folders (shards,
// machines) and aggregates them into the paper's Fig. 3 curves, Fig. 4 run-time split and
// its headline findings, each with mean, standard deviation and the number of trials.
//
// Merging: a trial is known by its id. The same id in two folders with the same results
// (status and views.csv, which is byte-identical for a seed) is kept once; with different
// results it is an error. Folders left `.partial`, or without a readable trial.json, are
// ignored and listed. Trials the experiments' experiment.json files expect but no folder
// holds are listed as missing.

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/experiments/experiment.h"

namespace canopy::experiments {

/// One finished trial, read back from its folder.
struct TrialResult {
  TrialSpec spec;
  std::string status;                    ///< "ok" or "failed".
  std::string message;                   ///< Why it failed.
  std::string folder;                    ///< Where it was read from.
  std::vector<double> coverage, entropy; ///< After each successful view (index v-1).
  std::vector<std::string> phases;       ///< The phase of each successful view ("initial", "nbv", ...).
  std::map<std::string, std::vector<double>> curves;  ///< records::curve_column_names() the trial's views.csv has.
  std::map<std::string, double> phase_s; ///< Wall time by mission phase.
  double wall_s = 0.0, sim_s = 0.0;
  int stops = 0, views_ok = 0, views_attempted = 0;
  std::map<std::string, int> failures;   ///< Failed view attempts by cause.
  /// The field's metrics at the end (field_metric_names(); absent or null in summary.json:
  /// not in the map, e.g. a centre error without a matched fruit).
  std::map<std::string, double> field;
  std::string fingerprint;               ///< What must agree between two copies of the trial.
};

/// A folder that was ignored.
struct IncompleteFolder {
  std::string path, reason;
};

/// The trials of several experiment folders, merged.
struct MergedTrials {
  std::vector<std::string> names;          ///< Experiment names.
  std::vector<TrialSpec> expected;         ///< Every trial the experiments list, in order.
  std::vector<TrialResult> trials;         ///< Present trials (ok or failed), in `expected` order.
  std::vector<std::string> missing;        ///< Expected ids no folder holds.
  std::vector<IncompleteFolder> incomplete;
};

/// A trial folder whose files are missing or do not read back whole (a truncated trial.json
/// or summary.json, a deleted views.csv): left out of the figures and listed.
class DamagedTrial : public InputError {
 public:
  using InputError::InputError;
};

/// Reads one trial folder (trials/<id>): its trial.json, and for an ok trial its mission's
/// results. Throws DamagedTrial saying why when a file is missing or does not read back whole
/// ("unreadable: ..." for the record, "damaged: ..." for an ok trial's results), and
/// InputError when a whole file holds an impossible value (a NaN coverage).
TrialResult read_trial(const std::string& dir);

/// Reads and merges experiment folders; a trial folder read_trial refuses is listed in
/// `incomplete` with why. Throws InputError for a folder that is not an experiment folder, for a trial present twice with different results (naming the trial
/// and both folders), or for two experiments that give one id different settings.
MergedTrials merge_experiment_folders(const std::vector<std::string>& dirs);

/// The report's files.
struct ExperimentReport {
  std::string curves_csv;   ///< method,label,p_gt,view,trials,sc_mean,sc_std,entropy_mean,entropy_std
  std::string runtime_csv;  ///< per method and P_gt: trials and mean/std of each Fig. 4 phase, totals, views
  /// The paper's headline findings beside ours, as blocks in order, each an object with a
  /// "kind": {"kind": "heading", "level", "text"}, {"kind": "paragraph", "text", "strong"},
  /// {"kind": "table", "header": [...], "rows": [[...]]}, {"kind": "list", "items": [...]}.
  /// findings.md and report.html (web/experiment_report.js) both render it.
  nlohmann::json findings = nlohmann::json::array();
  std::string findings_md;  ///< findings_markdown(findings).
  std::string field_curves_csv;  ///< per method, P_gt, metric and view: trials, mean and std (the field's metrics' curves)
  std::string field_csv;    ///< per method and P_gt: trials, mean and std of each of the field's metrics
  nlohmann::json trials_json;  ///< Every trial: id, status, message, source folder; missing; incomplete.
  /// Every gain against the truth (the oracle) per method label and P_gt, over the trials'
  /// candidates.csv (mission.record.candidates): label,p_gt,score,rounds,spearman,top1,top5,
  /// mean_oracle_rank,truth_share. Empty when no trial recorded candidates.
  std::string gain_truth_csv;
};

/// Aggregates merged trials (only trials with status ok enter the statistics).
ExperimentReport make_experiment_report(const MergedTrials& merged);

/// The findings' blocks (ExperimentReport::findings) as markdown (findings.md).
std::string findings_markdown(const nlohmann::json& findings);

/// The field's metrics a trial's summary.json gives at the end (its "final" and "motion_cost"
/// sections; the coverage at each time budget as sc_at_<T>s), in report order.
std::vector<std::string> field_metric_names(const std::vector<TrialResult>& trials);

}  // namespace canopy::experiments
