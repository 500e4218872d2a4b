#pragma once
// Job: report.html of an experiment's report folder (`canopy report`, docs/report.md): the
// findings, every table of the report, the curves of every trial as interactive plots (hover:
// method, P_gt, world, value) beside their means, and each trial linked to its own
// report.html. One file, opened from file:// with no server (web/experiment_report.js inlined).

#include <string>

#include <nlohmann/json.hpp>

#include "canopy/experiments/experiment_report.h"

namespace canopy::jobs {

/// The page's data: tables parsed from the report's CSV text, the trials with their curves and
/// the relative link from `report_dir` (the folder the page is published in) to each trial's
/// report.html ("" when the trial folder has none).
nlohmann::json experiment_page_data(const experiments::MergedTrials& merged, const experiments::ExperimentReport& report,
                                    const std::string& report_dir);

/// Writes report.html into `working_dir` (atomically); its links are relative to `report_dir`,
/// where the folder is published.
void write_experiment_page(const std::string& working_dir, const std::string& report_dir,
                           const experiments::MergedTrials& merged, const experiments::ExperimentReport& report);

}  // namespace canopy::jobs
