// canopy report: merges experiment folders (shards, machines) and writes report/: curves.csv,
// runtime.csv, trials.json, findings.md and the Fig. 3 / Fig. 4 figures (SVG, jobs/figures.h).
// The work is jobs::write_report (canopy/jobs/report_job.h); merging and aggregation live in
// canopy/experiments/experiment_report.h.

#include <spdlog/spdlog.h>

#include "canopy/common/interrupt.h"
#include "canopy/jobs/report_job.h"
#include "commands.h"

namespace canopy::cli {

void add_report_command(CLI::App& app) {
  struct Options {
    jobs::ReportJobParams job;
    bool no_plots = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("report", "Merge experiment folders and write the report (curves, run time, findings, report.html, plots)");
  sub->add_option("dirs", o->job.dirs, "Experiment folders (canopy experiment --out)")->required();
  sub->add_option("--out", o->job.out, "Report folder (default: <first folder>/report)");
  sub->add_flag("--no-plots", o->no_plots, "Skip the SVG figures");
  sub->callback([o] {
    o->job.plots = !o->no_plots;
    const InterruptScope interrupts;  // Ctrl-C / SIGTERM: nothing is published and nothing left behind
    o->job.stop_requested = [] { return interrupt_requested(); };
    const jobs::ReportJobResult r = jobs::write_report(o->job);
    const experiments::MergedTrials& merged = r.merged;
    spdlog::info("report: {} trials expected, {} ok, {} failed, {} missing, {} incomplete folders ignored; wrote {}/",
                 merged.expected.size(), r.ok, merged.trials.size() - r.ok, merged.missing.size(),
                 merged.incomplete.size(), r.out);
    for (const auto& id : merged.missing) spdlog::warn("missing trial: {}", id);
    for (const auto& i : merged.incomplete) spdlog::warn("incomplete folder ignored: {} ({})", i.path, i.reason);
  });
}

}  // namespace canopy::cli
