// Merging experiment folders and aggregating their trials (canopy/experiments/experiment_report.h).

#include "canopy/experiments/experiment_report.h"

#include "canopy/mission/oracle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"
#include "canopy/common/stats.h"
#include "canopy/mission/run_folder.h"
#include "canopy/mission/view_columns.h"

namespace canopy::experiments {

namespace fs = std::filesystem;

namespace {

nlohmann::json parse_json_file(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw InputError(p.string() + ": cannot be read");
  return nlohmann::json::parse(in);  // nlohmann::json::exception on bad text
}

void read_mission(const fs::path& mission, TrialResult* r) {
  const mission::RunFolder f = mission::read_run_folder(mission.string());
  r->coverage = f.coverage;
  r->entropy = f.entropy;
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
  for (const mission::ViewColumn* c : mission::final_figure_columns()) {
    const nlohmann::json* v = &s;
    std::stringstream path(c->final.path);
    for (std::string k; std::getline(path, k, '/');) v = &at(*v, k);
    take(c->final.key, *v);
    if (c->final.scale != 1.0 && r->field.count(c->final.key)) r->field[c->final.key] *= c->final.scale;
  }
  const nlohmann::json& cat = at(at(s, "motion_cost"), "coverage_at_time");
  if (cat.is_array())
    for (const nlohmann::json& e : cat)
      if (e.is_object() && e.contains("time_s") && e.contains("coverage"))
        take("sc_at_" + format_number(e.at("time_s").get<double>(), "%.6g") + "s", e.at("coverage"));
}

using Stat = SampleStats;
Stat stat(const std::vector<double>& v) { return sample_stats(v); }

std::string num(double x, const char* fmt = "%.6g") { return format_number(x, fmt); }
std::string pm(const Stat& s, const char* fmt = "%.3f") {
  if (s.n == 0) return "n/a";
  return num(s.mean, fmt) + " ± " + num(s.std, fmt) + " (n=" + std::to_string(s.n) + ")";
}

// A (method label, P_gt) group of ok trials, in the experiment's order.
struct Group {
  ExperimentMethod method;
  double p_gt = 1.0;
  std::vector<const TrialResult*> trials;
};

std::vector<Group> groups_of(const MergedTrials& m) {
  std::vector<Group> out;
  for (const TrialSpec& t : m.expected) {
    auto it = std::find_if(out.begin(), out.end(), [&](const Group& g) {
      return g.method.label == t.method.label && trial_id("m", g.p_gt, 1) == trial_id("m", t.p_gt, 1);
    });
    if (it == out.end()) out.push_back({t.method, t.p_gt, {}});
  }
  // Methods first, then P_gt from high (no noise) to low.
  std::stable_sort(out.begin(), out.end(), [](const Group& a, const Group& b) { return a.p_gt > b.p_gt; });
  std::vector<std::string> labels;
  for (const TrialSpec& t : m.expected)
    if (std::find(labels.begin(), labels.end(), t.method.label) == labels.end()) labels.push_back(t.method.label);
  std::stable_sort(out.begin(), out.end(), [&](const Group& a, const Group& b) {
    return std::find(labels.begin(), labels.end(), a.method.label) < std::find(labels.begin(), labels.end(), b.method.label);
  });
  for (const TrialResult& r : m.trials) {
    if (r.status != "ok") continue;
    for (Group& g : out)
      if (g.method.label == r.spec.method.label && trial_id("m", g.p_gt, 1) == trial_id("m", r.spec.p_gt, 1))
        g.trials.push_back(&r);
  }
  return out;
}

double category(const TrialResult& r, const std::vector<std::string>& phases) {
  double s = 0.0;
  for (const auto& p : phases) {
    const auto it = r.phase_s.find(p);
    if (it != r.phase_s.end()) s += it->second;
  }
  return s;
}

// The four phases of the paper's Fig. 4 (its "total run time").
double paper_total(const TrialResult& r) {
  double s = 0.0;
  for (std::size_t c = 0; c < 4; ++c) s += category(r, runtime_categories()[c].second);
  return s;
}

template <typename F>
Stat over(const Group& g, F f) {
  std::vector<double> v;
  for (const TrialResult* r : g.trials) v.push_back(f(*r));
  return stat(v);
}

std::string pgt_text(double p) { return num(p, "%.6g"); }

// Difference of two group means with its standard error; relative to `base`.
std::string diff_text(const Stat& a, const Stat& base, double scale, const char* unit) {
  if (a.n == 0 || base.n == 0) return "n/a";
  const double d = a.mean - base.mean;
  const double se = std::sqrt((a.n > 1 ? a.std * a.std / a.n : 0.0) + (base.n > 1 ? base.std * base.std / base.n : 0.0));
  std::string s = (d >= 0 ? "+" : "") + num(d * scale, "%.1f") + " ± " + num(se * scale, "%.1f") + unit;
  if (base.mean != 0.0) s += " (" + std::string(d >= 0 ? "+" : "") + num(100.0 * d / base.mean, "%.1f") + " %)";
  return s;
}

// " (within 2 standard errors: ...)" when the difference of the means is not resolved.
std::string resolution(const Stat& a, const Stat& b) {
  const double se = std::sqrt((a.n > 1 ? a.std * a.std / a.n : 0.0) + (b.n > 1 ? b.std * b.std / b.n : 0.0));
  if (std::fabs(a.mean - b.mean) >= 2.0 * se && a.n > 1 && b.n > 1) return "";
  return " — but within 2 standard errors (or n < 2), so not resolved by these " + std::to_string(a.n) + " and " +
         std::to_string(b.n) + " trials";
}

const Group* find_group(const std::vector<Group>& gs, const std::string& method, double p_gt) {
  for (const Group& g : gs)
    if (g.method.choice.name == method && trial_id("m", g.p_gt, 1) == trial_id("m", p_gt, 1)) return &g;
  return nullptr;
}

}  // namespace

std::vector<std::string> field_metric_names(const std::vector<TrialResult>& trials) {
  std::vector<std::string> names;
  for (const mission::ViewColumn* c : mission::final_figure_columns()) names.push_back(c->final.key);
  std::vector<std::pair<double, std::string>> budgets;
  for (const TrialResult& t : trials)
    for (const auto& [k, v] : t.field)
      if (k.rfind("sc_at_", 0) == 0 && std::find_if(budgets.begin(), budgets.end(), [&, &key = k](const auto& b) {
                                         return b.second == key;
                                       }) == budgets.end())
        budgets.emplace_back(std::atof(k.c_str() + 6), k);
  std::sort(budgets.begin(), budgets.end());
  for (const auto& b : budgets) names.push_back(b.second);
  return names;
}

const std::vector<std::pair<std::string, std::vector<std::string>>>& runtime_categories() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> c = {
      {"mapping", {"mapping"}},
      {"nbv_planning", {"clustering", "candidates", "filtering", "scoring", "nbv_planning"}},
      {"motion_planning", {"motion_planning"}},
      {"control", {"control"}},
      {"rendering", {"rendering"}},
      {"evaluation", {"evaluation"}},
  };
  return c;
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
      TrialResult r;
      r.folder = p.string();
      try {
        const nlohmann::json t = parse_json_file(p / "trial.json");
        r.spec = TrialSpec::from_json(t.at("trial"), (p / "trial.json").string());
        r.status = t.at("status").get<std::string>();
        r.message = t.value("message", std::string());
        if (r.spec.id != name) throw InputError("its trial.json describes trial " + r.spec.id);
        if (r.status != "ok" && r.status != "failed") throw InputError("unknown status '" + r.status + "'");
        r.fingerprint = r.status + (r.status == "ok" ? std::string() : "\n" + r.message);
      } catch (const std::exception& e) {
        m.incomplete.push_back({p.string(), std::string("unreadable: ") + e.what()});
        continue;
      }
      // A trial that says it is ok but whose results are malformed (NaN, a missing column) is
      // an error: averaging over it, or quietly leaving it out, would report wrong figures.
      if (r.status == "ok") {
        try {
          read_mission(p / "mission", &r);
        } catch (const InputError&) {
          throw;
        } catch (const std::exception& e) {
          throw InputError((p / "mission").string() + ": malformed results (" + e.what() + ")");
        }
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

// The paper's findings that findings.md holds an experiment against: the three methods it
// compares, by their registered names, and what it reports of them (its Fig. 4, run time by
// phase, and the text of its evaluation: final fruit SC, SC lost to noise, views per stop).
struct PaperClaims {
  const char* ours = "ours";
  const char* frontier = "frontier";
  const char* predefined = "predefined";
  int active_sc_gain_pct = 11;         // final fruit SC, both active methods over predefined scanning
  const char* noise_p_gt = "0.7";      // the noisy segmentation of its noise experiment
  int noise_sc_loss_pct = 17;          // final fruit SC lost to that noise
  int ours_less_time_pct = 8;          // total run time (Fig. 4), ours below frontier
  int active_more_time_pct = 45;       // total run time (Fig. 4), active methods above predefined (at least)
  int predefined_views_per_stop = 12;  // successful views per stop: 12 predefined + 12 more,
  int more_views_per_stop = 12;        // the same for every method
  int stops = 5;                       // 5 stops: 120 views in all
};
constexpr PaperClaims kPaperClaims{};

std::string pct(int p) { return std::to_string(p) + " %"; }

double final_sc(const TrialResult& t) { return t.coverage.empty() ? 0.0 : t.coverage.back(); }

// curves.csv: only trials that reached view v count at v (the `trials` column).
std::string curves_csv_text(const std::vector<Group>& groups) {
  std::string c = "method,label,p_gt,view,trials,sc_mean,sc_std,entropy_mean,entropy_std\n";
  for (const Group& g : groups) {
    std::vector<std::vector<double>> sc, h;
    for (const TrialResult* r : g.trials) {
      sc.push_back(r->coverage);
      h.push_back(r->entropy);
    }
    const std::vector<SampleStats> sc_curve = curve_stats(sc), h_curve = curve_stats(h);
    for (std::size_t v = 0; v < sc_curve.size(); ++v) {
      const Stat& a = sc_curve[v];
      const Stat& b = h_curve[v];
      c += g.method.choice.name + "," + g.method.label + "," + pgt_text(g.p_gt) + "," + std::to_string(v + 1) + "," +
           std::to_string(a.n) + "," + num(a.mean, "%.9g") + "," + num(a.std, "%.9g") + "," + num(b.mean, "%.9g") + "," +
           num(b.std, "%.9g") + "\n";
    }
  }
  return c;
}

// field_curves.csv: the field's per-view metrics, the same way (trials having the column).
std::string field_curves_csv_text(const std::vector<Group>& groups) {
  std::string fcv = "method,label,p_gt,metric,view,trials,mean,std\n";
  for (const Group& g : groups)
    for (const std::string& metric : mission::curve_column_names()) {
      std::vector<std::vector<double>> runs;
      for (const TrialResult* r : g.trials) {
        const auto it = r->curves.find(metric);
        if (it != r->curves.end()) runs.push_back(it->second);
      }
      if (runs.empty()) continue;
      const std::vector<SampleStats> curve = curve_stats(runs);
      for (std::size_t v = 0; v < curve.size(); ++v)
        fcv += g.method.choice.name + "," + g.method.label + "," + pgt_text(g.p_gt) + "," + metric + "," +
               std::to_string(v + 1) + "," + std::to_string(curve[v].n) + "," + num(curve[v].mean, "%.9g") + "," +
               num(curve[v].std, "%.9g") + "\n";
    }
  return fcv;
}

// runtime.csv: per group, mean and std of each category and the totals.
std::string runtime_csv_text(const std::vector<Group>& groups) {
  std::string r = "method,label,p_gt,trials";
  for (const auto& [cat, phases] : runtime_categories()) r += "," + cat + "_s_mean," + cat + "_s_std";
  r += ",paper_total_s_mean,paper_total_s_std,wall_s_mean,wall_s_std,simulated_s_mean,simulated_s_std,"
       "views_ok_mean,views_attempted_mean,final_sc_mean,final_sc_std\n";
  for (const Group& g : groups) {
    r += g.method.choice.name + "," + g.method.label + "," + pgt_text(g.p_gt) + "," + std::to_string(g.trials.size());
    for (const auto& [cat, phases] : runtime_categories()) {
      const Stat s = over(g, [&, &ph = phases](const TrialResult& t) { return category(t, ph); });
      r += "," + num(s.mean) + "," + num(s.std);
    }
    const Stat tot = over(g, paper_total), wall = over(g, [](const TrialResult& t) { return t.wall_s; }),
               sim = over(g, [](const TrialResult& t) { return t.sim_s; }),
               vok = over(g, [](const TrialResult& t) { return double(t.views_ok); }),
               vat = over(g, [](const TrialResult& t) { return double(t.views_attempted); }),
               sc = over(g, [](const TrialResult& t) { return t.coverage.empty() ? 0.0 : t.coverage.back(); });
    r += "," + num(tot.mean) + "," + num(tot.std) + "," + num(wall.mean) + "," + num(wall.std) + "," + num(sim.mean) +
         "," + num(sim.std) + "," + num(vok.mean) + "," + num(vat.mean) + "," + num(sc.mean) + "," + num(sc.std) + "\n";
  }
  return r;
}

// findings.md's title and the count of trials.
std::string findings_intro(const MergedTrials& m, std::size_t ok, std::size_t failed) {
  std::string names;
  for (const auto& n : m.names) names += (names.empty() ? "" : ", ") + n;
  std::string f = "# Findings: " + names + "\n\n";
  f += "Trials: " + std::to_string(m.expected.size()) + " expected, " + std::to_string(ok) + " ok, " +
       std::to_string(failed) + " failed, " + std::to_string(m.missing.size()) + " missing; " +
       std::to_string(m.incomplete.size()) + " incomplete folders ignored. Only ok trials enter the figures. " +
       "Figures are mean ± sample standard deviation over trials (n = trials); a difference is the difference of " +
       "the two means ± its standard error, and in brackets relative to the baseline's mean. SC is the fruit " +
       "surface coverage after the last successful view.\n\n";
  return f;
}

// The groups' P_gt values, from high (no noise) to low.
std::vector<double> p_gts_of(const std::vector<Group>& groups) {
  std::vector<double> pgts;
  for (const Group& g : groups)
    if (std::find_if(pgts.begin(), pgts.end(), [&](double p) { return pgt_text(p) == pgt_text(g.p_gt); }) == pgts.end())
      pgts.push_back(g.p_gt);
  std::sort(pgts.rbegin(), pgts.rend());
  return pgts;
}

// Section 1's figures at equal view counts: a method that ends with fewer successful views is
// compared where every method has taken as many (trials with fewer views have no figure there).
std::string equal_views_table(const std::vector<Group>& groups, const std::vector<double>& pgts) {
  const std::vector<int> counts = {30, 60, 90};
  std::string f = "\nThe same at equal view counts: fruit SC after the 30th, 60th and 90th successful view (trials "
                  "that ended before it have no figure there: n says how many had one).\n\n";
  f += "| P_gt | method | successful views | SC after 30 | after 60 | after 90 | final |\n|---|---|---|---|---|---|---|\n";
  for (double p : pgts)
    for (const Group& g : groups) {
      if (pgt_text(g.p_gt) != pgt_text(p)) continue;
      f += "| " + pgt_text(p) + " | " + g.method.label + " | " +
           pm(over(g, [](const TrialResult& t) { return double(t.views_ok); }), "%.1f");
      for (int n : counts) {
        std::vector<double> v;
        for (const TrialResult* t : g.trials)
          if (static_cast<int>(t->coverage.size()) >= n) v.push_back(t->coverage[static_cast<std::size_t>(n - 1)]);
        f += " | " + pm(stat(v));
      }
      f += " | " + pm(over(g, final_sc)) + " |\n";
    }
  return f;
}

// Section 1: active mapping vs predefined scanning, fruit SC at the end.
std::string coverage_section(const std::vector<Group>& groups, const std::vector<double>& pgts) {
  std::string f = "## 1. Active mapping vs predefined scanning: fruit SC at the end\n\n";
  f += "Paper: both active methods end with about " + pct(kPaperClaims.active_sc_gain_pct) +
       " more fruit surface coverage than predefined scanning.\n\n";
  f += "| P_gt | method | final SC | vs predefined (SC points) |\n|---|---|---|---|\n";
  for (double p : pgts) {
    const Group* pre = find_group(groups, kPaperClaims.predefined, p);
    for (const Group& g : groups) {
      if (pgt_text(g.p_gt) != pgt_text(p)) continue;
      const Stat s = over(g, final_sc);
      f += "| " + pgt_text(p) + " | " + g.method.label + " | " + pm(s) + " | " +
           (g.method.choice.name == kPaperClaims.predefined || !pre ? std::string("—")
                                                              : diff_text(s, over(*pre, final_sc), 100.0, "")) +
           " |\n";
    }
  }
  f += "\n";
  for (double p : pgts) {
    const Group* pre = find_group(groups, kPaperClaims.predefined, p);
    if (!pre || pre->trials.empty()) continue;
    for (const Group& g : groups) {
      if (pgt_text(g.p_gt) != pgt_text(p) || g.method.choice.name == kPaperClaims.predefined || g.trials.empty()) continue;
      const Stat a = over(g, final_sc), b = over(*pre, final_sc);
      const double d = a.mean - b.mean;
      f += "- P_gt " + pgt_text(p) + ", " + g.method.label + ": " +
           (d > 0 ? "higher than predefined scanning, as in the paper"
                  : "NOT higher than predefined scanning: differs from the paper") +
           " (" + num(100.0 * d, "%+.1f") + " points)" + resolution(a, b) + ".\n";
    }
  }
  return f + equal_views_table(groups, pgts);
}

// Section 2: SC lost to segmentation noise, each method at each noisy P_gt against the cleanest.
std::string noise_section(const std::vector<Group>& groups, const std::vector<double>& pgts) {
  std::string f = "\n## 2. SC lost to segmentation noise\n\n";
  f += "Paper: segmentation noise (P_gt " + std::string(kPaperClaims.noise_p_gt) + ") costs about " +
       pct(kPaperClaims.noise_sc_loss_pct) + " of the fruit surface coverage at the end.\n\n";
  if (pgts.size() < 2) return f + "Not measured: the experiment has one P_gt.\n";
  const double clean = pgts.front();
  std::string notes;
  f += "| method | SC at P_gt " + pgt_text(clean) + " | P_gt | SC with noise | change (SC points) |\n|---|---|---|---|---|\n";
  for (const Group& g : groups) {
    if (pgt_text(g.p_gt) != pgt_text(clean)) continue;
    for (double p : pgts) {
      if (pgt_text(p) == pgt_text(clean)) continue;
      const Group* noisy = nullptr;
      for (const Group& h : groups)
        if (h.method.label == g.method.label && pgt_text(h.p_gt) == pgt_text(p)) noisy = &h;
      if (!noisy) continue;
      const Stat a = over(g, final_sc), b = over(*noisy, final_sc);
      f += "| " + g.method.label + " | " + pm(a) + " | " + pgt_text(p) + " | " + pm(b) + " | " + diff_text(b, a, 100.0, "") +
           " |\n";
      if (a.n > 0 && b.n > 0 && a.mean > 0.0)
        notes += "- " + g.method.label + ", P_gt " + pgt_text(p) + ": " + num(100.0 * (a.mean - b.mean) / a.mean, "%.1f") +
                 " % of the SC lost (paper: about " + pct(kPaperClaims.noise_sc_loss_pct) + ")" + resolution(a, b) + ".\n";
    }
  }
  return f + "\n" + notes;
}

// Section 3's table: the paper's four phases, their total and the simulated time per group.
std::string runtime_md_table(const std::vector<Group>& groups) {
  std::string f = "| P_gt | method | mapping s | NBV planning s | motion planning s | control s | total s | simulated s |\n"
                  "|---|---|---|---|---|---|---|---|\n";
  for (const Group& g : groups) {
    f += "| " + pgt_text(g.p_gt) + " | " + g.method.label;
    for (std::size_t k = 0; k < 4; ++k) {
      const auto& phases = runtime_categories()[k].second;
      f += " | " + pm(over(g, [&](const TrialResult& t) { return category(t, phases); }), "%.2f");
    }
    f += " | " + pm(over(g, paper_total), "%.2f") + " | " + pm(over(g, [](const TrialResult& t) { return t.sim_s; }), "%.1f") +
         " |\n";
  }
  return f;
}

// Section 3: run time, ours against frontier and the active methods against predefined.
std::string runtime_section(const std::vector<Group>& groups, const std::vector<double>& pgts) {
  const std::string less = "-" + pct(kPaperClaims.ours_less_time_pct), more = "+" + pct(kPaperClaims.active_more_time_pct);
  const double more_factor = 1.0 + kPaperClaims.active_more_time_pct / 100.0;
  std::string f = "\n## 3. Run time\n\n";
  f += "Paper: cluster-centric planning (ours) needs " + pct(kPaperClaims.ours_less_time_pct) +
       " less total run time than the frontier-based planner; both active methods need more than " +
       pct(kPaperClaims.active_more_time_pct) +
       " more than predefined scanning. Total = mapping + NBV planning + motion "
       "planning + control (the paper's Fig. 4 phases; wall seconds on this machine). `control` is the wall time "
       "of simulating the moves; the robot's own time is the simulated time. Wall times also depend on what else the machine runs.\n\n";
  f += runtime_md_table(groups) + "\n";
  for (double p : pgts) {
    const Group* ours = find_group(groups, kPaperClaims.ours, p);
    const Group* fr = find_group(groups, kPaperClaims.frontier, p);
    const Group* pre = find_group(groups, kPaperClaims.predefined, p);
    if (ours && fr && !ours->trials.empty() && !fr->trials.empty()) {
      const Stat a = over(*ours, paper_total), b = over(*fr, paper_total);
      f += "- P_gt " + pgt_text(p) + ": " + ours->method.label + " vs " + fr->method.label + " total: " +
           diff_text(a, b, 1.0, " s") + "; " +
           (a.mean < b.mean ? "less than frontier, as in the paper (" + less + ")"
                            : "NOT less than frontier: differs from the paper (" + less + ")") +
           resolution(a, b) + ".\n";
    }
    if (pre && !pre->trials.empty())
      for (const Group* act : {ours, fr})
        if (act && !act->trials.empty()) {
          const Stat a = over(*act, paper_total), b = over(*pre, paper_total);
          f += "- P_gt " + pgt_text(p) + ": " + act->method.label + " vs " + pre->method.label + " total: " +
               diff_text(a, b, 1.0, " s") + "; " +
               (a.mean > more_factor * b.mean ? "more than " + more + ", as in the paper"
                                              : "NOT more than " + more + ": differs from the paper") +
               resolution(a, b) + ".\n";
        }
  }
  return f;
}

// Section 4: stops, successful and attempted views and failed attempts per stop, by cause.
std::string views_section(const std::vector<Group>& groups) {
  const int per_stop = kPaperClaims.predefined_views_per_stop + kPaperClaims.more_views_per_stop;
  std::string f = "\n## 4. Views and failures per stop\n\n";
  f += "Paper: every method executes the same number of successful views, " + std::to_string(per_stop) + " per stop (" +
       std::to_string(kPaperClaims.predefined_views_per_stop) + " predefined + " + std::to_string(kPaperClaims.more_views_per_stop) +
       " more), " + std::to_string(per_stop * kPaperClaims.stops) +
       " in all; it reports no failure counts, only that some best views are unreachable.\n\n";
  f += "| P_gt | method | stops | successful views / stop | attempted / stop | failed attempts / stop (by cause) |\n"
       "|---|---|---|---|---|---|\n";
  for (const Group& g : groups) {
    std::set<std::string> causes;
    for (const TrialResult* t : g.trials)
      for (const auto& [k, v] : t->failures) causes.insert(k);
    auto per_stop_of = [](double x, const TrialResult& t) { return t.stops > 0 ? x / t.stops : 0.0; };
    std::string by_cause;
    for (const std::string& k : causes) {
      const Stat s = over(g, [&](const TrialResult& t) {
        const auto it = t.failures.find(k);
        return per_stop_of(it == t.failures.end() ? 0.0 : it->second, t);
      });
      by_cause += (by_cause.empty() ? "" : ", ") + k + " " + num(s.mean, "%.2f") + " ± " + num(s.std, "%.2f");
    }
    f += "| " + pgt_text(g.p_gt) + " | " + g.method.label + " | " +
         pm(over(g, [](const TrialResult& t) { return double(t.stops); }), "%.0f") + " | " +
         pm(over(g, [&](const TrialResult& t) { return per_stop_of(t.views_ok, t); }), "%.1f") + " | " +
         pm(over(g, [&](const TrialResult& t) { return per_stop_of(t.views_attempted, t); }), "%.1f") + " | " +
         (by_cause.empty() ? std::string("none") : by_cause) + " |\n";
  }
  return f;
}

// A field metric over a group's trials that have it (finite).
Stat field_stat(const Group& g, const std::string& k) {
  std::vector<double> v;
  for (const TrialResult* t : g.trials) {
    const auto it = t->field.find(k);
    if (it != t->field.end() && std::isfinite(it->second)) v.push_back(it->second);
  }
  return stat(v);
}

// field.csv: every field metric's mean, std and n per group.
std::string field_csv_text(const std::vector<Group>& groups, const std::vector<std::string>& field) {
  std::string fc = "method,label,p_gt,trials";
  for (const std::string& k : field) fc += "," + k + "_mean," + k + "_std," + k + "_n";
  fc += "\n";
  for (const Group& g : groups) {
    fc += g.method.choice.name + "," + g.method.label + "," + pgt_text(g.p_gt) + "," + std::to_string(g.trials.size());
    for (const std::string& k : field) {
      const Stat s = field_stat(g, k);
      fc += "," + (s.n ? num(s.mean) : "") + "," + (s.n ? num(s.std) : "") + "," + std::to_string(s.n);
    }
    fc += "\n";
  }
  return fc;
}

// Section 5: the field's metrics at the end, one table per kind of metric.
std::string field_section(const std::vector<Group>& groups, const std::vector<std::string>& field) {
  std::string f = "\n## 5. The field's metrics at the end\n\n";
  f += "Fruit detection (map clusters matched one-to-one to the true ripe fruits), shape errors of the matched "
       "fruits, fruit-level completeness, the voxel precision of the fruit class, and motion cost "
       "(docs/metrics.md). Mean ± std over the trials that have the figure (n); a centre or volume "
       "error needs a matched fruit. All of them per group in field.csv.\n\n";
  // One table per report group of the column table, in its order; then the time budgets.
  std::vector<std::pair<std::string, std::vector<std::string>>> all_tables;
  std::map<std::string, const char*> formats;
  for (const mission::ViewColumn* c : mission::final_figure_columns()) {
    const std::string title = mission::report_group_title(c->final.group);
    if (all_tables.empty() || all_tables.back().first != title) all_tables.push_back({title, {}});
    all_tables.back().second.push_back(c->final.key);
    formats[c->final.key] = c->final.format;
  }
  std::vector<std::string> budget_keys;
  for (const std::string& k : field)
    if (k.rfind("sc_at_", 0) == 0) budget_keys.push_back(k);
  if (!budget_keys.empty()) all_tables.push_back({"Coverage reached by a simulated time budget", budget_keys});
  for (const auto& [title, keys] : all_tables) {
    f += "**" + title + "**\n\n| P_gt | method";
    for (const std::string& k : keys) f += " | " + k;
    f += " |\n|---|---";
    for (std::size_t i = 0; i < keys.size(); ++i) f += "|---";
    f += "|\n";
    for (const Group& g : groups) {
      f += "| " + pgt_text(g.p_gt) + " | " + g.method.label;
      for (const std::string& k : keys) f += " | " + pm(field_stat(g, k), formats.count(k) ? formats.at(k) : "%.3f");
      f += " |\n";
    }
    f += "\n";
  }
  return f;
}

// The closing list of failed, missing and incomplete trials.
std::string problems_section(const MergedTrials& m, std::size_t failed) {
  std::string f = "\n## Failed, missing and incomplete trials\n\n";
  if (failed == 0 && m.missing.empty() && m.incomplete.empty()) f += "None.\n";
  for (const TrialResult& t : m.trials)
    if (t.status != "ok") f += "- failed: " + t.spec.id + ": " + t.message + "\n";
  for (const std::string& id : m.missing) f += "- missing: " + id + "\n";
  for (const IncompleteFolder& i : m.incomplete) f += "- incomplete (ignored): " + fs::path(i.path).filename().string() + ": " + i.reason + "\n";
  return f;
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
    const std::string table = mission::gain_truth_csv(mission::gain_truth(files));
    std::stringstream ss(table);
    std::string line;
    std::getline(ss, line);  // header
    while (std::getline(ss, line)) out += g.method.label + "," + pgt_text(g.p_gt) + "," + line + "\n";
  }
  return out;
}

}  // namespace

ExperimentReport make_experiment_report(const MergedTrials& m) {
  ExperimentReport rep;
  const std::vector<Group> groups = groups_of(m);
  rep.curves_csv = curves_csv_text(groups);
  rep.field_curves_csv = field_curves_csv_text(groups);
  rep.runtime_csv = runtime_csv_text(groups);

  std::size_t ok = 0, failed = 0;
  for (const TrialResult& t : m.trials) (t.status == "ok" ? ok : failed)++;
  // The field's metrics: mean ± std over the trials that have each (docs/background/evaluation.md).
  std::vector<TrialResult> ok_trials;
  for (const TrialResult& t : m.trials)
    if (t.status == "ok") ok_trials.push_back(t);
  const std::vector<std::string> field = field_metric_names(ok_trials);
  rep.field_csv = field_csv_text(groups, field);
  const std::vector<double> pgts = p_gts_of(groups);
  rep.findings_md = findings_intro(m, ok, failed) + coverage_section(groups, pgts) + noise_section(groups, pgts) +
                    runtime_section(groups, pgts) + views_section(groups) + field_section(groups, field) +
                    problems_section(m, failed);

  rep.trials_json = trials_json_of(m);
  rep.gain_truth_csv = gain_truth_table(groups);
  return rep;
}

}  // namespace canopy::experiments
