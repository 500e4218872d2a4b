// canopy report's job (report_job.h): the stop request is polled before writing and before
// publishing, and either poll that fires leaves nothing behind (no folder, no .partial, no
// lock); without a request the folder is published. A signal-free check of what cli.interrupt
// can no longer time (the job now finishes about 20 ms after its first line).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/jobs/report_job.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;

// An experiment folder with no trials: the smallest one write_report accepts.
fs::path empty_experiment(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("canopy_report_job_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream(d / "experiment.json") << R"({"name": "empty", "trials": []})";
  return d;
}

// Counts the polls and asks to stop at poll `stop_at` (0: never).
ReportJobParams params_stopping_at(const fs::path& d, int stop_at, int* polls) {
  ReportJobParams p;
  p.dirs = {d.string()};
  p.out = (d / "report").string();
  p.plots = true;  // the figures are drawn between the two polls
  p.stop_requested = [stop_at, polls] { return ++*polls == stop_at; };
  return p;
}

void expect_nothing_left(const fs::path& d) {
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename(), "experiment.json") << "left behind: " << e.path();
}

TEST(ReportJob, AStopBeforeWritingLeavesNothing) {
  const fs::path d = empty_experiment("first");
  int polls = 0;
  EXPECT_THROW(write_report(params_stopping_at(d, 1, &polls)), Interrupted);
  EXPECT_EQ(polls, 1);
  expect_nothing_left(d);
}

TEST(ReportJob, AStopBeforePublishingRemovesWhatWasWritten) {
  const fs::path d = empty_experiment("second");
  int polls = 0;
  EXPECT_THROW(write_report(params_stopping_at(d, 2, &polls)), Interrupted);
  EXPECT_EQ(polls, 2);
  expect_nothing_left(d);
}

TEST(ReportJob, WithoutAStopTheFolderIsPublishedAfterTwoPolls) {
  const fs::path d = empty_experiment("none");
  int polls = 0;
  const ReportJobResult r = write_report(params_stopping_at(d, 0, &polls));
  EXPECT_EQ(polls, 2);
  EXPECT_EQ(r.out, (d / "report").string());
  EXPECT_TRUE(fs::exists(d / "report" / "curves.csv"));
  EXPECT_TRUE(fs::exists(d / "report" / "findings.md"));
  EXPECT_FALSE(fs::exists(d / "report.partial"));
  EXPECT_EQ(r.ok, 0u);
}

}  // namespace
}  // namespace canopy::jobs
