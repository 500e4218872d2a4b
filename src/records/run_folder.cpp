// The files a mission leaves, written and read back (run_folder.h).

#include "canopy/records/run_folder.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/csv.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/mapping/map_io.h"
#include "canopy/records/view_columns.h"

namespace canopy::records {

std::string views_csv(const MissionResult& r, const std::string& method) {
  std::string s = views_csv_header();
  for (const ViewRecord& v : r.views) s += views_csv_row(v, method);
  return s;
}

std::string timing_csv(const MissionResult& r) {
  const std::vector<WallPhase> phases = {WallPhase::kMotionPlanning, WallPhase::kControl, WallPhase::kRendering,
                                         WallPhase::kMapping, WallPhase::kEvaluation};
  std::vector<std::string> header = {"attempt"};
  for (const WallPhase p : phases) header.push_back(std::string(to_string(p)) + "_s");
  CsvWriter csv(header);
  for (const ViewRecord& v : r.views) {
    csv.add(v.attempt);
    for (const WallPhase p : phases) csv.add(v.times.get(to_string(p)));
    csv.end_row();
  }
  return csv.take();
}

nlohmann::json summary_json(const MissionResult& r) {
  JsonFields json;
  MissionSummary{const_cast<MissionResult&>(r)}.visit(json);
  return json.node;
}

std::vector<double> coverage_at_times(const MissionResult& r, const std::vector<double>& times_s) {
  std::vector<double> out;
  for (double T : times_s) {
    double c = 0.0;
    for (const ViewRecord& v : r.views)
      if (v.sim_time_s <= T) c = v.coverage;
    if (r.sim_time_s <= T) c = r.final_metrics.coverage;
    out.push_back(c);
  }
  return out;
}

nlohmann::json run_summary(const MissionResult& result, const settings::Settings& settings, const RunContext& ctx) {
  JsonFields json;
  MissionSummary{const_cast<MissionResult&>(result), &settings, &ctx}.visit(json);
  return json.node;
}

std::vector<FieldInfo> summary_fields() {
  MissionResult result;
  result.stops.emplace_back();
  const settings::Settings settings;
  const RunContext context;
  std::vector<FieldInfo> out;
  DescribeFields d(&out);
  MissionSummary{result, &settings, &context}.visit(d);
  return out;
}

std::string summary_fields_markdown() { return fields_markdown(summary_fields(), "key"); }

nlohmann::json write_run_folder(const std::string& dir, const MissionResult& result, const settings::Settings& settings,
                                const mapping::SemanticOcTree& map, const RunContext& ctx) {
  const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
  write_file_atomic(d + "views.csv", views_csv(result, settings.method.name));
  write_file_atomic(d + "timing.csv", timing_csv(result));
  write_file_atomic(d + "fruit_shapes.csv", evaluation::fruit_shapes_csv(result.final_metrics.detection));
  if (!result.candidates.empty()) write_file_atomic(d + "candidates.csv", candidates_csv(result.candidates));
  write_file_atomic(d + "settings.yaml", settings.to_yaml_text());
  mapping::save_map(map, d + "map.csm");
  mapping::export_ply(map, d + "map.ply");
  mapping::export_bt(map, d + "map.bt");
  const nlohmann::json summary = run_summary(result, settings, ctx);
  write_json_atomic(d + "summary.json", summary);
  return summary;
}

RunFolder read_run_folder(const std::string& dir) {
  RunFolder f;
  const std::string views_path = dir + "/views.csv";
  f.views_csv = read_file(views_path);
  std::stringstream in(f.views_csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv_line(line);
  auto col = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    throw InputError(views_path + ": no column '" + name + "'");
  };
  const std::size_t c_success = col("success"), c_cov = col("coverage"), c_ent = col("entropy");
  std::size_t c_phase = header.size();  // optional
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == "phase") c_phase = i;
  std::vector<std::pair<std::string, std::size_t>> curve_cols;  // the optional columns present
  for (const std::string& name : curve_column_names())
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) curve_cols.emplace_back(name, i);
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    const std::vector<std::string> fields = split_csv_line(line);
    if (fields.size() != header.size()) throw InputError(views_path + ": row " + std::to_string(row) + " has the wrong column count");
    if (fields[c_success] != "1") continue;
    double cov = 0.0, ent = 0.0;
    try {
      cov = c_stod(fields[c_cov]);
      ent = c_stod(fields[c_ent]);
    } catch (const std::exception&) {
      throw InputError(views_path + ": row " + std::to_string(row) + " has a coverage or entropy that is not a number");
    }
    if (!std::isfinite(cov) || !std::isfinite(ent) || cov < 0.0 || cov > 1.0 || ent < 0.0)
      throw InputError(views_path + ": row " + std::to_string(row) + " has coverage '" + fields[c_cov] + "' and entropy '" +
                       fields[c_ent] + "' (need a coverage in [0, 1] and a finite entropy >= 0)");
    f.coverage.push_back(cov);
    f.entropy.push_back(ent);
    f.phases.push_back(c_phase < fields.size() ? fields[c_phase] : std::string());
    for (const auto& [name, c] : curve_cols) {
      double x = std::numeric_limits<double>::quiet_NaN();
      if (!fields[c].empty()) {
        std::size_t used = 0;
        try {
          x = c_stod(fields[c], &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != fields[c].size())
          throw InputError(views_path + ": row " + std::to_string(row) + " has " + name + " '" + fields[c] +
                           "' that is not a number");
      }
      f.curves[name].push_back(x);
    }
  }
  const std::string summary_path = dir + "/summary.json";
  try {
    f.summary = nlohmann::json::parse(read_file(summary_path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(summary_path + ": not valid JSON (" + e.what() + ")");
  }
  return f;
}

}  // namespace canopy::records
