// The tables of a view's fields (view_columns.h): views.csv's header, a record's row reads back
// to the record's values, the report's figures are where summary.json keeps them, `canopy
// map`'s history keys stay what they were (and read back), and docs/commands.md holds its Markdown.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/records/run_folder.h"
#include "canopy/records/view_columns.h"

namespace canopy::records {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string item;
  std::stringstream ss(line);
  while (std::getline(ss, item, ',')) out.push_back(item);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::string line;
  std::stringstream ss(text);
  while (std::getline(ss, line)) out.push_back(line);
  return out;
}

// Two views with values a 9-digit field holds exactly: one that reached its goal (rotated
// 90 degrees about z) and one that failed, before any fruit was matched.
MissionResult two_views() {
  MissionResult r;
  ViewRecord a;
  a.attempt = 3;
  a.stop = 1;
  a.phase = ViewPhase::kNbv;
  a.source = "roi";
  a.success = true;
  a.T_goal.translation() = Vec3(0.5, -0.25, 1.125);
  a.T_reached.linear() = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  a.T_reached.translation() = Vec3(0.5, -0.25, 1.0);
  a.position_error_m = 0.125;
  a.angle_error_rad = M_PI / 180.0 * 2.5;
  a.gain = 12.5;
  a.cluster = 2;
  a.successful_views = 7;
  a.coverage = 0.375;
  a.entropy = 41.5;
  a.coverage_paper = 0.5, a.entropy_paper = 30.25, a.coverage_prototype = 0.375, a.entropy_prototype = 41.5;
  a.sim_time_s = 96.5;
  a.move_time_s = 4.25;
  a.truth_contacts = 1;
  a.self_contacts = 0;
  a.arm_path_rad = 2.75;
  a.base_travel_m = 1.5;
  a.fruits_sc50 = 0.5, a.fruits_sc80 = 0.25;
  a.fruit_clusters = 4, a.fruits_matched = 2;
  a.detection_precision = 0.5, a.detection_recall = 0.25, a.detection_f1 = 0.375;
  a.centre_error_m = 0.0125, a.voxel_volume_error = 0.75, a.ellipsoid_volume_error = 0.625;
  a.fruit_voxel_precision = 0.875, a.false_fruit_volume_m3 = 1.5e-05;
  ViewRecord b;
  b.attempt = 4;
  b.stop = 1;
  b.phase = ViewPhase::kPredefined;
  b.source = "predefined";
  b.success = false;
  b.failure = FailureCause::kNoIk;
  b.T_goal.translation() = Vec3(1.0, 2.0, 3.0);
  b.cluster = -1;
  b.centre_error_m = b.voxel_volume_error = b.ellipsoid_volume_error = std::nan("");
  r.views = {a, b};
  return r;
}

// The header of views.csv as the golden missions have it: the table must not reorder it.
TEST(ViewColumns, AreViewsCsvsHeader) {
  const std::string header =
      "attempt,stop,method,phase,source,success,failure,goal_x,goal_y,goal_z,reached_x,reached_y,reached_z,"
      "reached_qw,reached_qx,reached_qy,reached_qz,position_error_m,angle_error_deg,gain,cluster,successful_views,"
      "coverage,entropy,sim_time_s,move_time_s,truth_contacts,self_contacts,coverage_paper,entropy_paper,"
      "coverage_prototype,entropy_prototype,arm_path_rad,base_travel_m,fruits_sc50,fruits_sc80,fruit_clusters,"
      "fruits_matched,detection_precision,detection_recall,detection_f1,centre_error_m,voxel_volume_error,"
      "ellipsoid_volume_error,fruit_voxel_precision,false_fruit_volume_m3";
  EXPECT_EQ(views_csv(MissionResult(), "ours"), header + "\n");
  const std::vector<std::string> names = split(header);
  ASSERT_EQ(view_columns().size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(view_columns()[i].name, names[i]);
    EXPECT_EQ(&view_column(names[i]), &view_columns()[i]);
    EXPECT_NE(std::string(view_columns()[i].field.doc), "") << names[i];
  }
  EXPECT_THROW(view_column("no_such_column"), std::out_of_range);
}

// Every field of a row is the column's value; reals read back to the record's (exactly where
// the value has 9 digits or fewer); a failed view leaves its reached pose empty and an error
// without a match is empty.
TEST(ViewColumns, ARecordsRowReadsBackToItsValues) {
  const MissionResult r = two_views();
  const std::vector<std::string> rows = lines(views_csv(r, "ours"));
  ASSERT_EQ(rows.size(), 3u);
  for (std::size_t k = 0; k < 2; ++k) {
    JsonFields json;  // the record's own values, by field
    const_cast<ViewRecord&>(r.views[k]).visit(json, "ours");
    const std::vector<std::string> f = split(rows[k + 1]);
    ASSERT_EQ(f.size(), view_columns().size());
    for (std::size_t i = 0; i < f.size(); ++i) {
      const FieldInfo& c = view_columns()[i];
      const nlohmann::json& x = json.node.at(c.name);
      if (x.is_null()) {
        EXPECT_EQ(f[i], "") << c.name;
      } else if (c.type == FieldType::kReal) {
        const double want = x.get<double>();
        EXPECT_NEAR(std::stod(f[i]), want, 5e-9 * std::max(1.0, std::fabs(want))) << c.name;
      } else if (c.type == FieldType::kFlag) {
        EXPECT_EQ(f[i], x.get<bool>() ? "1" : "0") << c.name;
      } else if (c.type == FieldType::kInt) {
        EXPECT_EQ(std::stoll(f[i]), x.get<long long>()) << c.name;
      } else {
        EXPECT_EQ(f[i], x.get<std::string>()) << c.name;
      }
    }
  }
  const std::vector<std::string> a = split(rows[1]), b = split(rows[2]);
  const auto at = [](const std::vector<std::string>& f, const char* name) {
    for (std::size_t i = 0; i < view_columns().size(); ++i)
      if (view_columns()[i].name == std::string(name)) return f[i];
    return std::string("?");
  };
  EXPECT_EQ(at(a, "method"), "ours");
  EXPECT_EQ(at(a, "phase"), "nbv");
  EXPECT_EQ(at(a, "success"), "1");
  EXPECT_EQ(at(a, "goal_z"), "1.125");
  EXPECT_EQ(at(a, "angle_error_deg"), "2.5");
  EXPECT_EQ(at(a, "reached_qz"), format_number(std::sqrt(0.5)));
  EXPECT_EQ(at(a, "false_fruit_volume_m3"), "1.5e-05");
  EXPECT_EQ(at(a, "centre_error_m"), "0.0125");
  EXPECT_EQ(at(b, "success"), "0");
  EXPECT_EQ(at(b, "failure"), "no_ik");
  EXPECT_EQ(at(b, "cluster"), "-1");
  for (const char* name : {"reached_x", "reached_y", "reached_z", "reached_qw", "reached_qx", "reached_qy", "reached_qz",
                           "centre_error_m", "voxel_volume_error", "ellipsoid_volume_error"})
    EXPECT_EQ(at(b, name), "") << name;

  // The run folder's reader gives the successful view's coverage, entropy and curves back.
  const std::string dir = testing::TempDir() + "/view_columns_run";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_file_atomic(dir + "/views.csv", views_csv(r, "ours"));
  write_json_atomic(dir + "/summary.json", summary_json(r));
  const RunFolder f = read_run_folder(dir);
  EXPECT_EQ(f.coverage, std::vector<double>{0.375});
  EXPECT_EQ(f.entropy, std::vector<double>{41.5});
  ASSERT_EQ(f.curves.size(), curve_column_names().size());
  for (const std::string& name : curve_column_names())
    EXPECT_EQ(f.curves.at(name), std::vector<double>{views_json(r.views, "").at(name).at(0).get<double>()}) << name;
}

// The report's curves and figures at the end: unique, in the report's order, groups whole; each
// figure is where summary.json keeps it (a number, or null for an error without a match).
TEST(ViewColumns, ReportFiguresAreWhereTheSummaryKeepsThem) {
  EXPECT_EQ(curve_column_names(),
            (std::vector<std::string>{"fruits_sc80", "detection_f1", "fruit_voxel_precision", "sim_time_s"}));
  std::vector<std::string> keys;
  std::set<ReportGroup> closed;
  ReportGroup current = ReportGroup::kNone;
  const nlohmann::json summary = summary_json(two_views());
  for (const FieldInfo* c : final_figure_columns()) {
    const FinalFigure& fin = c->field.final;
    keys.push_back(fin.key);
    if (fin.group != current) {
      EXPECT_FALSE(closed.count(fin.group)) << c->name << ": its report group is split";
      closed.insert(current);
      current = fin.group;
    }
    EXPECT_NE(std::string(report_group_title(fin.group)), "") << c->name;
    const nlohmann::json* v = &summary;
    std::stringstream path(fin.path);
    for (std::string k; std::getline(path, k, '/');) {
      ASSERT_TRUE(v->is_object() && v->contains(k)) << fin.path;
      v = &v->at(k);
    }
    EXPECT_TRUE(v->is_number() || v->is_null()) << fin.path;
  }
  EXPECT_EQ(keys, (std::vector<std::string>{"detection_precision", "detection_recall", "detection_f1",
                                            "detection_centre_error_m", "detection_voxel_volume_error",
                                            "detection_ellipsoid_volume_error", "fruits_sc50", "fruits_sc80",
                                            "fruit_voxel_precision", "false_fruit_volume_cm3", "arm_path_rad",
                                            "base_travel_m", "simulated_time_s"}));
}

// `canopy map`'s history: the map's figures under the keys metrics.json has always had.
TEST(ViewColumns, MapHistoryHoldsTheMapsFigures) {
  evaluation::MapMetrics m;
  m.coverage = 0.25, m.total_entropy = 12.0, m.paper.coverage = 0.5, m.paper.entropy = 10.0;
  m.prototype.coverage = 0.25, m.prototype.entropy = 12.0, m.fruits_sc50 = 0.5, m.fruits_sc80 = 0.125;
  m.detection.f1 = 0.75, m.voxel_precision.precision = 0.875;
  const nlohmann::json want = {{"coverage", 0.25},         {"total_entropy", 12.0},     {"coverage_paper", 0.5},
                               {"coverage_prototype", 0.25}, {"entropy_paper", 10.0},  {"entropy_prototype", 12.0},
                               {"fruits_sc50", 0.5},         {"fruits_sc80", 0.125},    {"detection_f1", 0.75},
                               {"fruit_voxel_precision", 0.875}};
  EXPECT_EQ(map_history_metrics(m), want);
  // A record read from the history has the map's figures again (the report of canopy map).
  ViewRecord v;
  v.coverage = 0.9;
  v.attempt = 7;
  read_map_history(want, &v);
  EXPECT_EQ(v.coverage, 0.25);
  EXPECT_EQ(v.entropy, 12.0);
  EXPECT_EQ(v.detection_f1, 0.75);
  EXPECT_EQ(v.fruit_voxel_precision, 0.875);
  EXPECT_EQ(v.attempt, 7);  // what the history does not hold is kept
}

// docs/commands.md holds the table's Markdown between its markers (regenerate it from the
// text this test prints when they differ).
TEST(ViewColumns, DocsHoldTheTable) {
  const std::string doc = read_file("docs/commands.md");
  const std::string begin = "<!-- generated from the column table: records::view_columns_markdown() -->\n";
  const std::string end = "<!-- end of the generated table -->";
  const std::size_t a = doc.find(begin), b = doc.find(end);
  ASSERT_NE(a, std::string::npos) << "docs/commands.md lacks the marker " << begin;
  ASSERT_NE(b, std::string::npos) << "docs/commands.md lacks the marker " << end;
  EXPECT_EQ(doc.substr(a + begin.size(), b - a - begin.size()), view_columns_markdown())
      << "docs/commands.md's table of views.csv columns is out of date; it should read:\n"
      << view_columns_markdown();
}

}  // namespace
}  // namespace canopy::records
