#pragma once
// The figures of canopy's commands, drawn as SVG (common/svg_chart.h) from the data each
// command writes, in-process: a mission's sc_entropy.svg and runtime.svg (from its report
// data, which report.html shows too), an experiment report's fig3_entropy_coverage.svg,
// field_curves.svg, fig4_runtime.svg and gain_truth.svg (from its tables), the ablation's
// gains.svg and rays.svg, and visibility.svg. One plot path (docs/report.md#figures): no
// plotting library and no script.

#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/experiments/experiment_report.h"
#include "canopy/jobs/visibility_job.h"

namespace canopy::jobs {

/// File name -> SVG text.
using Figures = std::map<std::string, std::string>;

/// A mission's figures from its report data and wall line (mission_report_data):
/// sc_entropy.svg (fruit surface coverage and entropy after each successful view, stops
/// marked) and runtime.svg (wall time by plot category, the paper's Fig. 4 for this run).
Figures mission_figures(const nlohmann::json& report_data, const nlohmann::json& wall);

/// An experiment report's figures from its tables (the paper's Fig. 3 and 4, the field's
/// curves, every gain against the truth when the trials recorded candidates).
Figures experiment_figures(const experiments::ExperimentReport& report);

/// The ablation's figures from its summary.csv: gains.svg (per gain, our ray set) and
/// rays.svg (per ray set, OSAMCEP).
Figures ablation_figures(const std::string& summary_csv);

/// visibility.svg: detectability per camera position and of the best k positions, per seed
/// and pooled, beside Hemming et al.'s figures.
Figures visibility_figures(const VisibilitySummary& summary, const std::string& world_name);

/// Writes each figure into `dir` atomically.
void write_figures(const std::string& dir, const Figures& figures);

}  // namespace canopy::jobs
