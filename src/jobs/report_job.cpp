#include "canopy/jobs/report_job.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/jobs/experiment_page.h"
#include "canopy/jobs/figures.h"
#include "canopy/jobs/run_report.h"

namespace canopy::jobs {

ReportJobResult write_report(const ReportJobParams& params) {
  ReportJobResult r;
  r.merged = experiments::merge_experiment_folders(params.dirs);
  const experiments::ExperimentReport rep = experiments::make_experiment_report(r.merged);
  r.out = params.out.empty() ? (std::filesystem::path(params.dirs.front()) / "report").string() : params.out;
  spdlog::info("report: merged {} trial folders of {} expected ({} incomplete folders); writing {}/",
               r.merged.trials.size(), r.merged.expected.size(), r.merged.incomplete.size(), r.out);
  const auto check_stop = [&params] {
    if (params.stop_requested && params.stop_requested()) throw Interrupted("interrupted; nothing was written");
  };
  check_stop();
  StagedDir out(r.out, "report");
  write_file_atomic(out.path("curves.csv"), rep.curves_csv);
  write_file_atomic(out.path("runtime.csv"), rep.runtime_csv);
  write_file_atomic(out.path("findings.md"), rep.findings_md);
  write_file_atomic(out.path("field.csv"), rep.field_csv);
  write_file_atomic(out.path("field_curves.csv"), rep.field_curves_csv);
  write_json_atomic(out.path("trials.json"), rep.trials_json);
  if (!rep.gain_truth_csv.empty()) write_file_atomic(out.path("gain_truth.csv"), rep.gain_truth_csv);
  if (params.page && report_libraries_present()) write_experiment_page(out.working_dir(), r.out, r.merged, rep);
  else if (params.page) spdlog::warn("report.html skipped (needs Debian's libjs-three; run tools/deps.sh)");
  if (params.plots) write_figures(out.working_dir(), experiment_figures(rep));
  check_stop();
  out.commit();
  for (const auto& t : r.merged.trials) r.ok += t.status == "ok";
  return r;
}

}  // namespace canopy::jobs
