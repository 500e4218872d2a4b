// findings.md: an experiment's figures held against the paper's findings (report_groups.h).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/stats.h"
#include "canopy/common/value_text.h"
#include "canopy/records/view_columns.h"
#include "report_groups.h"

namespace canopy::experiments::report {

namespace fs = std::filesystem;

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
// compared where every method has taken as many (trials with fewer views have no figure there);
// beside them the SC reached by each simulated time budget (`field`'s sc_at_ keys), the robot's
// own time, which a method cannot save by ending its stops early.
std::string equal_views_table(const std::vector<Group>& groups, const std::vector<double>& pgts,
                              const std::vector<std::string>& field) {
  const std::vector<int> counts = {30, 60, 90};
  std::vector<std::string> budgets;
  for (const std::string& k : field)
    if (k.rfind("sc_at_", 0) == 0) budgets.push_back(k);
  std::string f = "\nThe same at equal view counts: fruit SC after the 30th, 60th and 90th successful view (trials "
                  "that ended before it have no figure there: n says how many had one)";
  f += budgets.empty() ? std::string(".\n\n")
                       : ", and at equal simulated time: the SC reached by each time budget of the robot's own time "
                         "(mission.record.time_budgets_s; a trial that ended before it counts its final SC).\n\n";
  f += "| P_gt | method | successful views | SC after 30 | after 60 | after 90 | final |";
  for (const std::string& k : budgets) f += " SC by " + k.substr(6, k.size() - 7) + " s |";
  f += "\n|---|---|---|---|---|---|---|";
  for (std::size_t i = 0; i < budgets.size(); ++i) f += "---|";
  f += "\n";
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
      f += " | " + pm(over(g, final_sc)) + " |";
      for (const std::string& k : budgets) f += " " + pm(field_stat(g, k)) + " |";
      f += "\n";
    }
  return f;
}

// Section 1: active mapping vs predefined scanning, fruit SC at the end.
std::string coverage_section(const std::vector<Group>& groups, const std::vector<double>& pgts,
                             const std::vector<std::string>& field) {
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
  return f + equal_views_table(groups, pgts, field);
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
  for (const records::ViewColumn* c : records::final_figure_columns()) {
    const std::string title = records::report_group_title(c->final.group);
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

}  // namespace

std::string findings_markdown(const MergedTrials& m, const std::vector<Group>& groups,
                              const std::vector<std::string>& field) {
  std::size_t ok = 0, failed = 0;
  for (const TrialResult& t : m.trials) (t.status == "ok" ? ok : failed)++;
  const std::vector<double> pgts = p_gts_of(groups);
  return findings_intro(m, ok, failed) + coverage_section(groups, pgts, field) + noise_section(groups, pgts) +
         runtime_section(groups, pgts) + views_section(groups) + field_section(groups, field) +
         problems_section(m, failed);
}

}  // namespace canopy::experiments::report
