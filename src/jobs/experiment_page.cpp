// report.html of an experiment report (experiment_page.h).

#include "canopy/jobs/experiment_page.h"

#include <filesystem>
#include <sstream>

#include "canopy/common/data_dir.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/run_report.h"

namespace canopy::jobs {

namespace {

// A CSV text as {name, header, rows}; numeric cells stay strings (the page prints them as written).
nlohmann::json csv_table(const std::string& name, const std::string& text) {
  nlohmann::json t = {{"name", name}, {"header", nlohmann::json::array()}, {"rows", nlohmann::json::array()}};
  std::istringstream in(text);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    nlohmann::json cells = nlohmann::json::array();
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (line.back() == ',') cells.push_back("");
    if (first) t["header"] = cells;
    else t["rows"].push_back(cells);
    first = false;
  }
  return t;
}

}  // namespace

nlohmann::json experiment_page_data(const experiments::MergedTrials& merged, const experiments::ExperimentReport& rep,
                                    const std::string& report_dir) {
  namespace fs = std::filesystem;
  nlohmann::json d;
  d["kind"] = "experiment";
  d["names"] = merged.names;
  d["findings"] = rep.findings;
  nlohmann::json tables = nlohmann::json::array();
  tables.push_back(csv_table("curves.csv", rep.curves_csv));
  tables.push_back(csv_table("runtime.csv", rep.runtime_csv));
  tables.push_back(csv_table("field.csv", rep.field_csv));
  tables.push_back(csv_table("field_curves.csv", rep.field_curves_csv));
  if (!rep.gain_truth_csv.empty()) tables.push_back(csv_table("gain_truth.csv", rep.gain_truth_csv));
  d["tables"] = tables;
  const fs::path base = fs::absolute(fs::path(report_dir)).lexically_normal();
  nlohmann::json trials = nlohmann::json::array();
  for (const experiments::TrialResult& t : merged.trials) {
    nlohmann::json j = {{"id", t.spec.id}, {"label", t.spec.method.label}, {"p_gt", t.spec.p_gt}, {"seed", t.spec.seed},
                        {"world", t.spec.world_seed ? "world seed " + std::to_string(*t.spec.world_seed) : "world file's seed"},
                        {"status", t.status}, {"message", t.message}, {"views_ok", t.views_ok}, {"wall_s", t.wall_s}};
    nlohmann::json sc = nlohmann::json::array(), h = nlohmann::json::array();
    for (double c : t.coverage) sc.push_back(std::round(c * 1e4) / 1e4);
    for (double e : t.entropy) h.push_back(std::round(e * 1e3) / 1e3);
    j["sc"] = sc;
    j["entropy"] = h;
    const fs::path page = fs::absolute(fs::path(t.folder) / "mission" / "report.html").lexically_normal();
    j["link"] = fs::exists(page) ? page.lexically_relative(base).generic_string() : "";
    trials.push_back(j);
  }
  d["trials"] = trials;
  d["missing"] = merged.missing;
  nlohmann::json incomplete = nlohmann::json::array();
  for (const auto& f : merged.incomplete) incomplete.push_back({{"path", f.path}, {"reason", f.reason}});
  d["incomplete"] = incomplete;
  return d;
}

void write_experiment_page(const std::string& working_dir, const std::string& report_dir,
                           const experiments::MergedTrials& merged, const experiments::ExperimentReport& rep) {
  const std::string scripts = report_scripts("web/experiment_report.js");
  const std::string css = read_file(find_data_file("web/report.css"));
  const std::string d = working_dir.empty() || working_dir.back() == '/' ? working_dir : working_dir + "/";
  write_file_atomic(d + "report.html", report_page("canopy experiment report", scripts,
                                                   experiment_page_data(merged, rep, report_dir), nlohmann::json::object(), css));
}

}  // namespace canopy::jobs
