// canopy report: merges experiment folders (shards, machines) and writes report/: curves.csv,
// runtime.csv, trials.json, findings.md and the Fig. 3 / Fig. 4 plots (tools/plot_experiment.py).
// Merging and aggregation live in canopy/experiments/experiment_report.h.

#include <spdlog/spdlog.h>

#include <filesystem>

#include "canopy/common/io.h"
#include "canopy/common/process.h"
#include "canopy/experiments/experiment_report.h"
#include "commands.h"

namespace canopy::cli {

void add_report_command(CLI::App& app) {
  struct Options {
    std::vector<std::string> dirs;
    std::string out;
    bool no_plots = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("report", "Merge experiment folders and write the report (curves, run time, findings, plots)");
  sub->add_option("dirs", o->dirs, "Experiment folders (canopy experiment --out)")->required();
  sub->add_option("--out", o->out, "Report folder (default: <first folder>/report)");
  sub->add_flag("--no-plots", o->no_plots, "Skip the PNG plots");
  sub->callback([o] {
    const experiments::MergedTrials merged = experiments::merge_experiment_folders(o->dirs);
    const experiments::ExperimentReport rep = experiments::make_experiment_report(merged);
    const std::string out_path = o->out.empty() ? (std::filesystem::path(o->dirs.front()) / "report").string() : o->out;
    StagedDir out(out_path, "report");
    write_file_atomic(out.path("curves.csv"), rep.curves_csv);
    write_file_atomic(out.path("runtime.csv"), rep.runtime_csv);
    write_file_atomic(out.path("findings.md"), rep.findings_md);
    write_file_atomic(out.path("field.csv"), rep.field_csv);
    write_file_atomic(out.path("field_curves.csv"), rep.field_curves_csv);
    write_json_atomic(out.path("trials.json"), rep.trials_json);
    if (!rep.gain_truth_csv.empty()) write_file_atomic(out.path("gain_truth.csv"), rep.gain_truth_csv);
    if (!o->no_plots) {
      const std::string script = find_data_file("tools/plot_experiment.py");
      const ProcessStatus plot = run_process({"/usr/bin/python3", script, out.working_dir()});
      if (!plot.ok()) spdlog::warn("plots failed (needs python3-matplotlib): {}: {}", script, plot.describe());
    }
    out.commit();
    std::size_t ok = 0;
    for (const auto& t : merged.trials) ok += t.status == "ok";
    spdlog::info("report: {} trials expected, {} ok, {} failed, {} missing, {} incomplete folders ignored; wrote {}/",
                 merged.expected.size(), ok, merged.trials.size() - ok, merged.missing.size(), merged.incomplete.size(),
                 out_path);
    for (const auto& id : merged.missing) spdlog::warn("missing trial: {}", id);
    for (const auto& i : merged.incomplete) spdlog::warn("incomplete folder ignored: {} ({})", i.path, i.reason);
  });
}

}  // namespace canopy::cli
