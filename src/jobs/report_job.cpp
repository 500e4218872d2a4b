#include "canopy/jobs/report_job.h"

#include <filesystem>

#include "canopy/common/io.h"
#include "canopy/jobs/plots.h"

namespace canopy::jobs {

ReportJobResult write_report(const ReportJobParams& params) {
  ReportJobResult r;
  r.merged = experiments::merge_experiment_folders(params.dirs);
  const experiments::ExperimentReport rep = experiments::make_experiment_report(r.merged);
  r.out = params.out.empty() ? (std::filesystem::path(params.dirs.front()) / "report").string() : params.out;
  StagedDir out(r.out, "report");
  write_file_atomic(out.path("curves.csv"), rep.curves_csv);
  write_file_atomic(out.path("runtime.csv"), rep.runtime_csv);
  write_file_atomic(out.path("findings.md"), rep.findings_md);
  write_file_atomic(out.path("field.csv"), rep.field_csv);
  write_file_atomic(out.path("field_curves.csv"), rep.field_curves_csv);
  write_json_atomic(out.path("trials.json"), rep.trials_json);
  if (!rep.gain_truth_csv.empty()) write_file_atomic(out.path("gain_truth.csv"), rep.gain_truth_csv);
  if (params.plots) draw_plots("tools/plot_experiment.py", out.working_dir(), r.out);
  out.commit();
  for (const auto& t : r.merged.trials) r.ok += t.status == "ok";
  return r;
}

}  // namespace canopy::jobs
