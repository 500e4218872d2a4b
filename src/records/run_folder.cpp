// The files a mission leaves, written and read back (run_folder.h).

#include "canopy/records/run_folder.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
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
  const auto num = [](double x) { return format_number(x); };
  const std::vector<std::string> phases = {phase::kMotionPlanning, phase::kControl, phase::kRendering, phase::kMapping,
                                          phase::kEvaluation};
  std::string s = "attempt";
  for (const auto& p : phases) s += "," + p + "_s";
  s += "\n";
  for (const ViewRecord& v : r.views) {
    s += std::to_string(v.attempt);
    for (const auto& p : phases) s += "," + num(v.times.get(p));
    s += "\n";
  }
  return s;
}

nlohmann::json summary_json(const MissionResult& r) {
  nlohmann::json j;
  j["complete"] = r.complete;
  j["end_reason"] = r.end_reason;
  j["views_attempted"] = r.views.size();
  j["views_successful"] = r.successful_views();
  j["failures"] = r.failures;
  j["unstable_faults"] = r.unstable_faults;
  j["overlapped_moves"] = {{"started", r.overlapped_moves}, {"kept", r.overlapped_kept}};
  if (!r.zero_coverage_reason.empty()) j["zero_coverage_reason"] = r.zero_coverage_reason;
  int truth_contacts = 0, base_contacts = 0;
  for (const auto& v : r.views) truth_contacts += v.truth_contacts;
  nlohmann::json stops = nlohmann::json::array();
  for (const StopRecord& s : r.stops) {
    base_contacts += s.base_truth_contacts;
    stops.push_back({{"stop", s.stop},
                     {"goal", {s.goal.x_m, s.goal.y_m, s.goal.yaw_rad}},
                     {"reached", {s.reached.x_m, s.reached.y_m, s.reached.yaw_rad}},
                     {"reached_goal", s.reached_goal},
                     {"base_truth_contacts", s.base_truth_contacts},
                     {"initial_attempted", s.initial_attempted},
                     {"initial_successful", s.initial_ok},
                     {"initial_target_points", s.initial_target_points},
                     {"initial_true_target_pixels", s.initial_true_target_pixels},
                     {"initial_scan_saw_no_target", s.initial_ok > 0 && s.initial_target_points == 0},
                     {"nbv_attempted", s.nbv_attempted},
                     {"nbv_successful", s.nbv_ok},
                     {"scripted_replaced", s.scripted_replaced},
                     {"replacement_attempts", s.replacement_attempts},
                     {"refused", s.refused},
                     {"guarded", s.guarded},
                     {"exploration_rounds", s.exploration_rounds},
                     {"rounds", s.rounds},
                     {"failures", s.failures},
                     {"end_reason", s.end_reason},
                     {"end", s.end},
                     {"budget", s.budget},
                     {"successful", s.initial_ok + s.nbv_ok},
                     {"start_repairs", s.start_repairs},
                     {"sim_time_s", s.sim_time_s}});
  }
  j["stops"] = stops;
  int replaced = 0, replacement_attempts = 0, refused = 0, guarded = 0, exploration_rounds = 0;
  for (const StopRecord& s : r.stops) {
    replaced += s.scripted_replaced;
    replacement_attempts += s.replacement_attempts;
    refused += s.refused;
    guarded += s.guarded;
    exploration_rounds += s.exploration_rounds;
  }
  j["refused"] = refused;
  j["guarded"] = guarded;
  j["exploration_rounds"] = exploration_rounds;
  int repairs = 0;
  for (const StopRecord& s : r.stops) repairs += s.start_repairs;
  j["start_repairs"] = repairs;
  j["scripted_replaced"] = replaced;
  j["replacement_attempts"] = replacement_attempts;
  bool all_reached = !r.stops.empty();
  for (const StopRecord& s : r.stops) all_reached = all_reached && s.reached_goal;
  j["all_stops_reached"] = all_reached;
  j["contacts"] = {{"arm_truth_contact_checks", truth_contacts}, {"base_truth_contact_checks", base_contacts}};
  const nlohmann::json metrics = r.final_metrics.to_json();
  j["final"] = {{"metrics_rule", metrics["rule"]},
                {"fruit_coverage", r.final_metrics.coverage},
                {"fruit_entropy", r.final_metrics.total_entropy},
                {"fruit_points", r.final_metrics.points},
                {"target_fruits", r.final_metrics.fruits.size()},
                {"non_target_fruits", r.final_metrics.non_target_fruits},
                {"rules", metrics["rules"]},
                {"fruits_sc50", metrics["fruits_sc50"]},
                {"fruits_sc80", metrics["fruits_sc80"]},
                {"detection", metrics["detection"]},
                {"fruit_voxel_precision", metrics["fruit_voxel_precision"]}};
  j["motion_cost"] = {{"arm_path_rad", r.arm_path_rad},
                      {"base_travel_m", r.base_travel_m},
                      {"simulated_time_s", r.sim_time_s}};
  j["simulated_time_s"] = r.sim_time_s;
  j["wall_time_s"] = r.wall_time_s;
  j["wall_time_by_phase_s"] = r.times.totals();
  return j;
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
  nlohmann::json summary = summary_json(result);
  const std::vector<double>& budgets = settings.mission.record.time_budgets_s;
  const std::vector<double> reached = coverage_at_times(result, budgets);
  nlohmann::json at = nlohmann::json::array();
  for (std::size_t i = 0; i < budgets.size(); ++i) at.push_back({{"time_s", budgets[i]}, {"coverage", reached[i]}});
  summary["motion_cost"]["coverage_at_time"] = at;
  summary["method"] = {{"name", settings.method.name}, {"gain", settings.method.gain}, {"rays", settings.method.rays}};
  const nbv::ViewPlannerEntry* entry = nbv::find_view_planner(settings.method.name);
  summary["method"]["reads_ground_truth"] = entry && entry->reads_ground_truth;
  summary["seed"] = ctx.seed;
  summary["p_gt"] = settings.mapping.extractor.p_gt;
  summary["labels"] = perception::to_string(settings.mapping.extractor.source);
  if (ctx.world)
    summary["world"] = {{"file", ctx.world_file},
                        {"plants", ctx.world->plants.size()},
                        {"fruits", ctx.world->truth.fruits.size()},
                        {"triangles", ctx.world->triangle_count()},
                        {"spec", ctx.world->spec.to_json()}};
  summary["settings_file"] = "settings.yaml";
  summary["files"] = {"views.csv", "timing.csv", "fruit_shapes.csv", "settings.yaml", "map.csm", "map.ply", "map.bt"};
  if (!result.candidates.empty()) summary["files"].push_back("candidates.csv");
  if (!ctx.video.is_null()) summary["video"] = ctx.video;
  return summary;
}

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
