// The run folder (records/run_folder.h), written and read in one place: what write_run_folder
// writes reads back (the successful views' curves, the summary), the summary lists the files
// written, coverage at a time is the last attempt's by then, and a damaged folder is an input
// error naming the file.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/records/run_folder.h"

namespace canopy::records {
namespace {

namespace fs = std::filesystem;

MissionResult three_attempts() {
  MissionResult r;
  ViewRecord a;
  a.attempt = 0;
  a.success = true;
  a.coverage = 0.25;
  a.entropy = 12.5;
  a.sim_time_s = 10.0;
  a.successful_views = 1;
  ViewRecord b;
  b.attempt = 1;
  b.success = false;
  b.failure = FailureCause::kNoIk;
  b.coverage = 0.25;
  b.entropy = 12.5;
  b.sim_time_s = 12.0;
  b.successful_views = 1;
  ViewRecord c = a;
  c.attempt = 2;
  c.coverage = 0.5;
  c.entropy = 8.0;
  c.sim_time_s = 20.0;
  c.successful_views = 2;
  r.views = {a, b, c};
  r.sim_time_s = 25.0;
  r.final_metrics.coverage = 0.625;
  r.complete = true;
  return r;
}

TEST(RunFolder, WhatIsWrittenReadsBack) {
  const fs::path dir = fs::path(::testing::TempDir()) / "run_folder";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const MissionResult r = three_attempts();
  const settings::Settings s = settings::Settings::defaults(default_robot_config());
  const mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  RunContext ctx;
  ctx.seed = 7;
  const nlohmann::json written = write_run_folder(dir.string(), r, s, map, ctx);
  for (const auto& f : written.at("files")) EXPECT_TRUE(fs::exists(dir / f.get<std::string>())) << f;
  EXPECT_EQ(written.at("seed"), 7);
  EXPECT_EQ(written.at("method").at("name"), "ours");
  EXPECT_EQ(read_file((dir / "settings.yaml").string()), s.to_yaml_text());
  const RunFolder back = read_run_folder(dir.string());
  EXPECT_EQ(back.views_csv, views_csv(r, "ours"));
  EXPECT_EQ(back.coverage, (std::vector<double>{0.25, 0.5}));  // the successful views only
  EXPECT_EQ(back.entropy, (std::vector<double>{12.5, 8.0}));
  EXPECT_EQ(back.summary, written);
  fs::remove_all(dir);
}

TEST(RunFolder, CoverageAtATimeIsTheLastAttemptsByThen) {
  const MissionResult r = three_attempts();
  EXPECT_EQ(coverage_at_times(r, {5.0, 10.0, 19.0, 20.0, 30.0}),
            (std::vector<double>{0.0, 0.25, 0.25, 0.5, 0.625}));  // after the end: the final coverage
}

TEST(RunFolder, ADamagedFolderNamesTheFile) {
  const fs::path dir = fs::path(::testing::TempDir()) / "run_folder_damaged";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string csv = views_csv(three_attempts(), "ours");
  const auto error = [&](const std::string& views, const std::string& summary) {
    write_file_atomic((dir / "views.csv").string(), views);
    if (summary.empty()) fs::remove(dir / "summary.json");
    else write_file_atomic((dir / "summary.json").string(), summary);
    try {
      read_run_folder(dir.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error(csv, "{}").find("(no error)"), 0u);
  EXPECT_NE(error(csv + "1,2,3\n", "{}").find("views.csv: row 5 has the wrong column count"), std::string::npos);
  EXPECT_NE(error(csv, "{not json").find("summary.json: not valid JSON"), std::string::npos);
  EXPECT_NE(error(csv, "").find("summary.json"), std::string::npos);
  EXPECT_NE(error("attempt,stop\n", "{}").find("views.csv: no column 'success'"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace canopy::records
