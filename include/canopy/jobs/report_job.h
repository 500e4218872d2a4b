#pragma once
// Job: merge experiment folders (shards, machines) and write the report folder: curves.csv,
// runtime.csv, field.csv, field_curves.csv, trials.json, findings.md, gain_truth.csv (when the
// trials recorded candidates), report.html (experiment_page.h) and the figures (figures.h: SVG).

#include <functional>
#include <string>
#include <vector>

#include "canopy/experiments/experiment_report.h"

namespace canopy::jobs {

/// What write_report needs.
struct ReportJobParams {
  std::vector<std::string> dirs;  ///< Experiment folders (canopy experiment --out).
  std::string out;                ///< Report folder; "" is <first folder>/report.
  bool plots = false;             ///< Draw the SVG figures (figures.h).
  bool page = true;               ///< Write report.html (experiment_page.h).
  /// Polled before writing and before publishing (may be null): true ends the job with
  /// Interrupted and nothing written (no folder, no .partial, no lock).
  std::function<bool()> stop_requested;
};

/// What it merged and where it wrote.
struct ReportJobResult {
  experiments::MergedTrials merged;
  std::string out;                ///< The report folder written.
  std::size_t ok = 0;             ///< Trials with status "ok".
};

/// Merges the folders, makes the report and publishes the report folder.
ReportJobResult write_report(const ReportJobParams& params);

}  // namespace canopy::jobs
