// Merging experiment folders and aggregating their trials (canopy/experiments/experiment_report.h).

#include "canopy/experiments/experiment_report.h"

#include "canopy/records/candidates_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "canopy/common/csv.h"
#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/stats.h"
#include "canopy/records/run_folder.h"
#include "canopy/records/view_columns.h"

namespace canopy::experiments {

namespace fs = std::filesystem;

namespace {

nlohmann::json parse_json_file(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw InputError(p.string() + ": cannot be read");
  return nlohmann::json::parse(in);  // nlohmann::json::exception on bad text
}

void read_mission(const fs::path& mission, TrialResult* r) {
  const records::RunFolder f = records::read_run_folder(mission.string());
  r->coverage = f.coverage;
  r->entropy = f.entropy;
  r->phases = f.phases;
  r->curves = f.curves;
  const nlohmann::json& s = f.summary;
  for (auto it = s.at("wall_time_by_phase_s").begin(); it != s.at("wall_time_by_phase_s").end(); ++it)
    r->phase_s[it.key()] = it.value().get<double>();
  r->wall_s = s.at("wall_time_s").get<double>();
  r->sim_s = s.at("simulated_time_s").get<double>();
  r->stops = static_cast<int>(s.at("stops").size());
  r->views_ok = s.at("views_successful").get<int>();
  r->views_attempted = s.at("views_attempted").get<int>();
  for (auto it = s.at("failures").begin(); it != s.at("failures").end(); ++it) r->failures[it.key()] = it.value().get<int>();
  r->fingerprint += "\n" + f.views_csv;
  // The field's metrics (summaries written before them have none).
  const auto take = [&](const std::string& name, const nlohmann::json& v) {
    if (v.is_number()) r->field[name] = v.get<double>();
  };
  const nlohmann::json none;
  const auto at = [&](const nlohmann::json& j, const std::string& k) -> const nlohmann::json& {
    return j.is_object() && j.contains(k) ? j.at(k) : none;
  };
  // Each per-view column's figure at the end, where the column table says summary.json holds it.
  for (const records::FieldInfo* c : records::final_figure_columns()) {
    const nlohmann::json* v = &s;
    std::stringstream path(c->field.final.path);
    for (std::string k; std::getline(path, k, '/');) v = &at(*v, k);
    take(c->field.final.key, *v);
    if (c->field.final.scale != 1.0 && r->field.count(c->field.final.key)) r->field[c->field.final.key] *= c->field.final.scale;
  }
  const nlohmann::json& cat = at(at(s, "motion_cost"), "coverage_at_time");
  if (cat.is_array())
    for (const nlohmann::json& e : cat)
      if (e.is_object() && e.contains("time_s") && e.contains("coverage"))
        take("sc_at_" + format_number(e.at("time_s").get<double>(), NumberFormat::kDigits6) + "s", e.at("coverage"));
}

}  // namespace

TrialResult read_trial(const std::string& dir) {
  const fs::path p(dir);
  TrialResult r;
  r.folder = p.string();
  try {
    const nlohmann::json t = parse_json_file(p / "trial.json");
    r.spec = TrialSpec::from_json(t.at("trial"), (p / "trial.json").string());
    r.status = t.at("status").get<std::string>();
    r.message = t.value("message", std::string());
    if (r.spec.id != p.filename().string()) throw InputError("its trial.json describes trial " + r.spec.id);
    if (r.status != "ok" && r.status != "failed") throw InputError("unknown status '" + r.status + "'");
    r.fingerprint = r.status + (r.status == "ok" ? std::string() : "\n" + r.message);
  } catch (const std::exception& e) {
    throw DamagedTrial(std::string("unreadable: ") + e.what());
  }
  if (r.status != "ok") return r;
  // An ok trial's results must read back whole: a missing or truncated file is damage (left
  // out and listed; --resume runs the trial again); a whole file holding an impossible value
  // (a NaN coverage) is an error, since averaging over it or leaving it out quietly would
  // report wrong figures.
  const fs::path mission = p / "mission";
  try {
    const std::string views = read_file((mission / "views.csv").string());
    const std::size_t header_end = views.find('\n');
    const std::size_t columns = std::count(views.begin(), views.begin() + static_cast<std::ptrdiff_t>(
                                                                               std::min(header_end, views.size())), ',');
    std::stringstream rows(views.substr(std::min(header_end, views.size())));
    for (std::string line; std::getline(rows, line);)
      if (!line.empty() && static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) != columns)
        throw InputError((mission / "views.csv").string() + ": a row of another length (truncated?)");
    if (header_end == std::string::npos || views.back() != '\n')
      throw InputError((mission / "views.csv").string() + ": does not end with a whole line (truncated?)");
    if (!nlohmann::json::accept(read_file((mission / "summary.json").string())))
      throw InputError((mission / "summary.json").string() + ": not valid JSON (truncated?)");
  } catch (const std::exception& e) {
    throw DamagedTrial(std::string("damaged: an ok trial whose mission/ does not read back (") + e.what() + ")");
  }
  try {
    read_mission(mission, &r);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(mission.string() + ": malformed results (" + e.what() + ")");
  }
  return r;
}

std::vector<std::string> field_metric_names(const std::vector<TrialResult>& trials) {
  std::vector<std::string> names;
  for (const records::FieldInfo* c : records::final_figure_columns()) names.push_back(c->field.final.key);
  std::vector<std::pair<double, std::string>> budgets;
  for (const TrialResult& t : trials)
    for (const auto& [k, v] : t.field)
      if (k.rfind("sc_at_", 0) == 0 && std::find_if(budgets.begin(), budgets.end(), [&, &key = k](const auto& b) {
                                         return b.second == key;
                                       }) == budgets.end())
        budgets.emplace_back(c_strtod(k.c_str() + 6, nullptr), k);
  std::sort(budgets.begin(), budgets.end());
  for (const auto& b : budgets) names.push_back(b.second);
  return names;
}

MergedTrials merge_experiment_folders(const std::vector<std::string>& dirs) {
  if (dirs.empty()) throw InputError("report: no experiment folder given");
  MergedTrials m;
  std::map<std::string, TrialSpec> expected_by_id;
  std::map<std::string, std::size_t> present;  // id -> index in m.trials
  for (const std::string& dir : dirs) {
    const fs::path manifest = fs::path(dir) / "experiment.json";
    if (!fs::is_directory(dir) || !fs::exists(manifest))
      throw InputError(dir + ": not an experiment folder (no experiment.json; `canopy experiment --out` writes one)");
    nlohmann::json j;
    try {
      j = parse_json_file(manifest);
      const std::string name = j.at("name").get<std::string>();
      if (std::find(m.names.begin(), m.names.end(), name) == m.names.end()) m.names.push_back(name);
      for (const auto& t : j.at("trials")) {
        const TrialSpec spec = TrialSpec::from_json(t, manifest.string());
        const auto it = expected_by_id.find(spec.id);
        if (it == expected_by_id.end()) {
          expected_by_id[spec.id] = spec;
          m.expected.push_back(spec);
        } else if (it->second.to_json() != spec.to_json()) {
          throw InputError(manifest.string() + ": trial " + spec.id + " is described differently in another folder");
        }
      }
    } catch (const nlohmann::json::exception& e) {
      throw InputError(manifest.string() + ": not a valid experiment.json (" + e.what() + ")");
    }
    const fs::path trials = fs::path(dir) / "trials";
    if (!fs::is_directory(trials)) continue;
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(trials)) entries.push_back(e.path());
    std::sort(entries.begin(), entries.end());
    for (const fs::path& p : entries) {
      const std::string name = p.filename().string();
      if (!fs::is_directory(p)) continue;
      if (name.size() > 8 && name.compare(name.size() - 8, 8, ".partial") == 0) {
        m.incomplete.push_back({p.string(), "in flight or killed (.partial)"});
        continue;
      }
      // A trial whose files are damaged (a truncated summary.json, a deleted views.csv) is left
      // out and listed with why, never averaged: `experiment --resume` runs it again.
      TrialResult r;
      try {
        r = read_trial(p.string());
      } catch (const DamagedTrial& e) {
        m.incomplete.push_back({p.string(), e.what()});
        continue;
      }
      const auto it = present.find(r.spec.id);
      if (it == present.end()) {
        present[r.spec.id] = m.trials.size();
        m.trials.push_back(std::move(r));
      } else if (m.trials[it->second].fingerprint != r.fingerprint) {
        throw InputError("trial " + r.spec.id + " is in " + m.trials[it->second].folder + " and " + r.folder +
                         " with different results (" +
                         (m.trials[it->second].status != r.status ? "status " + m.trials[it->second].status + " vs " + r.status
                                                                  : std::string("views.csv differs")) +
                         ")");
      }
    }
  }
  for (const TrialResult& r : m.trials)
    if (!expected_by_id.count(r.spec.id))
      throw InputError(r.folder + ": trial " + r.spec.id + " is not listed in any experiment.json given");
  // Present trials in the experiments' order; missing ones listed.
  std::vector<TrialResult> ordered;
  for (const TrialSpec& t : m.expected) {
    const auto it = present.find(t.id);
    if (it == present.end()) m.missing.push_back(t.id);
    else ordered.push_back(std::move(m.trials[it->second]));
  }
  m.trials = std::move(ordered);
  return m;
}

namespace {

using namespace report;

// curves.csv: only trials that reached view v count at v (the `trials` column).
std::string curves_csv_text(const std::vector<Group>& groups) {
  CsvWriter c({"method", "label", "p_gt", "view", "trials", "sc_mean", "sc_std", "entropy_mean", "entropy_std"});
  for (const Group& g : groups) {
    std::vector<std::vector<double>> sc, h;
    for (const TrialResult* r : g.trials) {
      sc.push_back(r->coverage);
      h.push_back(r->entropy);
    }
    const std::vector<SampleStats> sc_curve = curve_stats(sc), h_curve = curve_stats(h);
    for (std::size_t v = 0; v < sc_curve.size(); ++v)
      c.add(g.method.choice.name).add(g.method.label).add(pgt_text(g.p_gt)).add(v + 1).add(sc_curve[v].n)
          .add(sc_curve[v].mean).add(sc_curve[v].std).add(h_curve[v].mean).add(h_curve[v].std).end_row();
  }
  return c.take();
}

// field_curves.csv: the field's per-view metrics, the same way (trials having the column).
std::string field_curves_csv_text(const std::vector<Group>& groups) {
  CsvWriter fcv({"method", "label", "p_gt", "metric", "view", "trials", "mean", "std"});
  for (const Group& g : groups)
    for (const std::string& metric : records::curve_column_names()) {
      std::vector<std::vector<double>> runs;
      for (const TrialResult* r : g.trials) {
        const auto it = r->curves.find(metric);
        if (it != r->curves.end()) runs.push_back(it->second);
      }
      if (runs.empty()) continue;
      const std::vector<SampleStats> curve = curve_stats(runs);
      for (std::size_t v = 0; v < curve.size(); ++v)
        fcv.add(g.method.choice.name).add(g.method.label).add(pgt_text(g.p_gt)).add(metric).add(v + 1)
            .add(curve[v].n).add(curve[v].mean).add(curve[v].std).end_row();
    }
  return fcv.take();
}

// runtime.csv: per group, mean and std of each category and the totals.
std::string runtime_csv_text(const std::vector<Group>& groups) {
  std::vector<std::string> header = {"method", "label", "p_gt", "trials"};
  for (const records::PlotCategoryInfo& c : records::plot_categories()) {
    header.push_back(std::string(to_string(c.category)) + "_s_mean");
    header.push_back(std::string(to_string(c.category)) + "_s_std");
  }
  for (const char* k : {"paper_total_s_mean", "paper_total_s_std", "wall_s_mean", "wall_s_std", "simulated_s_mean",
                        "simulated_s_std", "views_ok_mean", "views_attempted_mean", "final_sc_mean", "final_sc_std"})
    header.push_back(k);
  CsvWriter r(header);
  constexpr NumberFormat k6 = NumberFormat::kDigits6;
  for (const Group& g : groups) {
    r.add(g.method.choice.name).add(g.method.label).add(pgt_text(g.p_gt)).add(g.trials.size());
    for (const records::PlotCategoryInfo& c : records::plot_categories()) {
      const Stat s = over(g, [&c](const TrialResult& t) { return category(t, c); });
      r.add(s.mean, k6).add(s.std, k6);
    }
    const Stat tot = over(g, paper_total), wall = over(g, [](const TrialResult& t) { return t.wall_s; }),
               sim = over(g, [](const TrialResult& t) { return t.sim_s; }),
               vok = over(g, [](const TrialResult& t) { return double(t.views_ok); }),
               vat = over(g, [](const TrialResult& t) { return double(t.views_attempted); }),
               sc = over(g, [](const TrialResult& t) { return t.coverage.empty() ? 0.0 : t.coverage.back(); });
    for (const double x : {tot.mean, tot.std, wall.mean, wall.std, sim.mean, sim.std, vok.mean, vat.mean, sc.mean, sc.std})
      r.add(x, k6);
    r.end_row();
  }
  return r.take();
}

// field.csv: every field metric's mean, std and n per group.
std::string field_csv_text(const std::vector<Group>& groups, const std::vector<std::string>& field) {
  std::vector<std::string> header = {"method", "label", "p_gt", "trials"};
  for (const std::string& k : field)
    for (const char* part : {"_mean", "_std", "_n"}) header.push_back(k + part);
  CsvWriter fc(header);
  for (const Group& g : groups) {
    fc.add(g.method.choice.name).add(g.method.label).add(pgt_text(g.p_gt)).add(g.trials.size());
    for (const std::string& k : field) {
      const Stat s = field_stat(g, k);
      if (s.n) fc.add(s.mean, NumberFormat::kDigits6).add(s.std, NumberFormat::kDigits6);
      else fc.add_empty().add_empty();
      fc.add(s.n);
    }
    fc.end_row();
  }
  return fc.take();
}

// trials.json: every trial's status and folder, the missing trials and the folders ignored.
nlohmann::json trials_json_of(const MergedTrials& m) {
  nlohmann::json tj = nlohmann::json::array();
  for (const TrialResult& t : m.trials)
    tj.push_back({{"id", t.spec.id}, {"status", t.status}, {"message", t.message}, {"folder", t.folder}});
  nlohmann::json inc = nlohmann::json::array();
  for (const IncompleteFolder& i : m.incomplete) inc.push_back({{"folder", i.path}, {"reason", i.reason}});
  return {{"experiments", m.names}, {"trials", tj}, {"missing", m.missing}, {"incomplete", inc}};
}

// gain_truth.csv: the trials' candidates.csv, per group ("" when no trial recorded them).
std::string gain_truth_table(const std::vector<Group>& groups) {
  std::string out;
  for (const Group& g : groups) {
    std::vector<std::string> files;
    for (const TrialResult* t : g.trials) {
      const fs::path f = fs::path(t->folder) / "mission" / "candidates.csv";
      if (fs::exists(f)) files.push_back(f.string());
    }
    if (files.empty()) continue;
    if (out.empty()) out = "label,p_gt,score,rounds,spearman,top1,top5,mean_oracle_rank,truth_share\n";
    const std::string table = records::gain_truth_csv(records::gain_truth(files));
    std::stringstream ss(table);
    std::string line;
    std::getline(ss, line);  // header
    while (std::getline(ss, line)) out += g.method.label + "," + pgt_text(g.p_gt) + "," + line + "\n";
  }
  return out;
}

}  // namespace

std::string findings_markdown(const nlohmann::json& findings) {
  // Blocks one after the other, a blank line between them.
  std::string md;
  const auto row = [](const nlohmann::json& cells) {
    std::string r = "|";
    for (const auto& c : cells) r += " " + c.get<std::string>() + " |";
    return r + "\n";
  };
  for (const nlohmann::json& b : findings) {
    const std::string kind = b.at("kind").get<std::string>();
    if (!md.empty()) md += "\n";
    if (kind == "heading") {
      md += std::string(b.at("level").get<std::size_t>(), '#') + " " + b.at("text").get<std::string>() + "\n";
    } else if (kind == "paragraph") {
      const std::string mark = b.value("strong", false) ? "**" : "";
      md += mark + b.at("text").get<std::string>() + mark + "\n";
    } else if (kind == "table") {
      md += row(b.at("header")) + "|";
      for (std::size_t i = 0; i < b.at("header").size(); ++i) md += "---|";
      md += "\n";
      for (const auto& r : b.at("rows")) md += row(r);
    } else if (kind == "list") {
      for (const auto& item : b.at("items")) md += "- " + item.get<std::string>() + "\n";
    } else {
      throw std::logic_error("findings: unknown block kind '" + kind + "'");
    }
  }
  return md;
}

ExperimentReport make_experiment_report(const MergedTrials& m) {
  ExperimentReport rep;
  const std::vector<report::Group> groups = report::groups_of(m);
  rep.curves_csv = curves_csv_text(groups);
  rep.field_curves_csv = field_curves_csv_text(groups);
  rep.runtime_csv = runtime_csv_text(groups);
  // The field's metrics: mean ± std over the trials that have each (docs/background/evaluation.md).
  std::vector<TrialResult> ok_trials;
  for (const TrialResult& t : m.trials)
    if (t.status == "ok") ok_trials.push_back(t);
  const std::vector<std::string> field = field_metric_names(ok_trials);
  rep.field_csv = field_csv_text(groups, field);
  rep.findings = report::findings_json(m, groups, field);
  rep.findings_md = findings_markdown(rep.findings);
  rep.trials_json = trials_json_of(m);
  rep.gain_truth_csv = gain_truth_table(groups);
  return rep;
}

}  // namespace canopy::experiments
