// The findings: an experiment's figures held against the paper's findings, as blocks of
// structured data (experiment_report.h: findings_markdown renders them as findings.md, and
// web/experiment_report.js as the page's section).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

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

using Row = std::vector<std::string>;

// The findings' blocks (findings.h: heading, paragraph, table, list), appended in order.
struct Blocks {
  nlohmann::json list = nlohmann::json::array();
  void heading(int level, const std::string& text) { list.push_back({{"kind", "heading"}, {"level", level}, {"text", text}}); }
  void paragraph(const std::string& text, bool strong = false) {
    list.push_back({{"kind", "paragraph"}, {"text", text}, {"strong", strong}});
  }
  void table(const Row& header, const std::vector<Row>& rows) {
    list.push_back({{"kind", "table"}, {"header", header}, {"rows", rows}});
  }
  void items(const std::vector<std::string>& items) {
    if (!items.empty()) list.push_back({{"kind", "list"}, {"items", items}});
  }
};

// The title and the count of trials.
void findings_intro(const MergedTrials& m, std::size_t ok, std::size_t failed, Blocks* b) {
  std::string names;
  for (const auto& n : m.names) names += (names.empty() ? "" : ", ") + n;
  b->heading(1, "Findings: " + names);
  b->paragraph("Trials: " + std::to_string(m.expected.size()) + " expected, " + std::to_string(ok) + " ok, " +
               std::to_string(failed) + " failed, " + std::to_string(m.missing.size()) + " missing; " +
               std::to_string(m.incomplete.size()) + " incomplete folders ignored. Only ok trials enter the figures. " +
               "Figures are mean ± sample standard deviation over trials (n = trials); a difference is the difference of " +
               "the two means ± its standard error, and in brackets relative to the baseline's mean. SC is the fruit " +
               "surface coverage after the last successful view.");
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
void equal_views_table(const std::vector<Group>& groups, const std::vector<double>& pgts,
                       const std::vector<std::string>& field, Blocks* b) {
  std::vector<std::string> budgets;
  for (const std::string& k : field)
    if (k.rfind("sc_at_", 0) == 0) budgets.push_back(k);
  b->paragraph(std::string("The same at equal view counts: fruit SC after the 30th, 60th and 90th successful view "
                           "(trials that ended before it have no figure there: n says how many had one)") +
               (budgets.empty() ? "."
                                : ", and at equal simulated time: the SC reached by each time budget of the robot's own "
                                  "time (mission.record.time_budgets_s; a trial that ended before it counts its final SC)."));
  std::vector<Row> rows;
  for (double p : pgts)
    for (const Group& g : groups) {
      if (pgt_text(g.p_gt) != pgt_text(p)) continue;
      Row r = {pgt_text(p), g.method.label, pm(over(g, [](const TrialResult& t) { return double(t.views_ok); }), "%.1f")};
      for (int n : kEqualViewCounts) {
        std::vector<double> v;
        for (const TrialResult* t : g.trials)
          if (static_cast<int>(t->coverage.size()) >= n) v.push_back(t->coverage[static_cast<std::size_t>(n - 1)]);
        r.push_back(pm(stat(v)));
      }
      r.push_back(pm(over(g, final_sc)));
      for (const std::string& k : budgets) r.push_back(pm(field_stat(g, k)));
      rows.push_back(r);
    }
  std::vector<std::string> header = {"P_gt", "method", "successful views", "SC after 30", "after 60", "after 90", "final"};
  for (const std::string& k : budgets) header.push_back("SC by " + k.substr(6, k.size() - 7) + " s");
  b->table(header, rows);
}

void coverage_section(const std::vector<Group>& groups, const std::vector<double>& pgts,
                      const std::vector<std::string>& field, Blocks* b) {
  b->heading(2, "1. Active mapping vs predefined scanning: fruit SC at the end");
  b->paragraph("Paper: both active methods end with about " + pct(kPaperClaims.active_sc_gain_pct) +
               " more fruit surface coverage than predefined scanning.");
  std::vector<Row> rows;
  for (double p : pgts) {
    const Group* pre = find_group(groups, kPaperClaims.predefined, p);
    for (const Group& g : groups) {
      if (pgt_text(g.p_gt) != pgt_text(p)) continue;
      const Stat s = over(g, final_sc);
      rows.push_back({pgt_text(p), g.method.label, pm(s),
                      g.method.choice.name == kPaperClaims.predefined || !pre ? std::string("—")
                                                                             : diff_text(s, over(*pre, final_sc), 100.0, "")});
    }
  }
  b->table({"P_gt", "method", "final SC", "vs predefined (SC points)"}, rows);
  std::vector<std::string> notes;
  for (double p : pgts) {
    const Group* pre = find_group(groups, kPaperClaims.predefined, p);
    if (!pre || pre->trials.empty()) continue;
    for (const Group& g : groups) {
      if (pgt_text(g.p_gt) != pgt_text(p) || g.method.choice.name == kPaperClaims.predefined || g.trials.empty()) continue;
      const Stat a = over(g, final_sc), c = over(*pre, final_sc);
      const double d = a.mean - c.mean;
      notes.push_back("P_gt " + pgt_text(p) + ", " + g.method.label + ": " +
                      (d > 0 ? "higher than predefined scanning, as in the paper"
                             : "NOT higher than predefined scanning: differs from the paper") +
                      " (" + num(100.0 * d, "%+.1f") + " points)" + resolution(a, c) + ".");
    }
  }
  b->items(notes);
  equal_views_table(groups, pgts, field, b);
}

// Section 2: SC lost to segmentation noise, each method at each noisy P_gt against the cleanest.
void noise_section(const std::vector<Group>& groups, const std::vector<double>& pgts, Blocks* b) {
  b->heading(2, "2. SC lost to segmentation noise");
  b->paragraph("Paper: segmentation noise (P_gt " + std::string(kPaperClaims.noise_p_gt) + ") costs about " +
               pct(kPaperClaims.noise_sc_loss_pct) + " of the fruit surface coverage at the end.");
  if (pgts.size() < 2) return b->paragraph("Not measured: the experiment has one P_gt.");
  const double clean = pgts.front();
  std::vector<std::string> notes;
  std::vector<Row> rows;
  for (const Group& g : groups) {
    if (pgt_text(g.p_gt) != pgt_text(clean)) continue;
    for (double p : pgts) {
      if (pgt_text(p) == pgt_text(clean)) continue;
      const Group* noisy = nullptr;
      for (const Group& h : groups)
        if (h.method.label == g.method.label && pgt_text(h.p_gt) == pgt_text(p)) noisy = &h;
      if (!noisy) continue;
      const Stat a = over(g, final_sc), c = over(*noisy, final_sc);
      rows.push_back({g.method.label, pm(a), pgt_text(p), pm(c), diff_text(c, a, 100.0, "")});
      if (a.n > 0 && c.n > 0 && a.mean > 0.0)
        notes.push_back(g.method.label + ", P_gt " + pgt_text(p) + ": " + num(100.0 * (a.mean - c.mean) / a.mean, "%.1f") +
                        " % of the SC lost (paper: about " + pct(kPaperClaims.noise_sc_loss_pct) + ")" + resolution(a, c) + ".");
    }
  }
  b->table({"method", "SC at P_gt " + pgt_text(clean), "P_gt", "SC with noise", "change (SC points)"}, rows);
  b->items(notes);
}

// Section 3's table: the paper's four phases, their total and the simulated time per group.
void runtime_table(const std::vector<Group>& groups, Blocks* b) {
  std::vector<Row> rows;
  for (const Group& g : groups) {
    Row r = {pgt_text(g.p_gt), g.method.label};
    for (const records::PlotCategoryInfo& c : records::plot_categories())
      if (c.paper) r.push_back(pm(over(g, [&c](const TrialResult& t) { return category(t, c); }), "%.2f"));
    r.push_back(pm(over(g, paper_total), "%.2f"));
    r.push_back(pm(over(g, [](const TrialResult& t) { return t.sim_s; }), "%.1f"));
    rows.push_back(r);
  }
  b->table({"P_gt", "method", "mapping s", "NBV planning s", "motion planning s", "control s", "total s", "simulated s"}, rows);
}

// Section 3: run time, ours against frontier and the active methods against predefined.
void runtime_section(const std::vector<Group>& groups, const std::vector<double>& pgts, Blocks* b) {
  const std::string less = "-" + pct(kPaperClaims.ours_less_time_pct), more = "+" + pct(kPaperClaims.active_more_time_pct);
  const double more_factor = 1.0 + kPaperClaims.active_more_time_pct / 100.0;
  b->heading(2, "3. Run time");
  b->paragraph("Paper: cluster-centric planning (ours) needs " + pct(kPaperClaims.ours_less_time_pct) +
               " less total run time than the frontier-based planner; both active methods need more than " +
               pct(kPaperClaims.active_more_time_pct) +
               " more than predefined scanning. Total = mapping + NBV planning + motion "
               "planning + control (the paper's Fig. 4 phases; wall seconds on this machine). Control is the wall time "
               "of simulating the moves; the robot's own time is the simulated time. Wall times also depend on what else "
               "the machine runs.");
  runtime_table(groups, b);
  std::vector<std::string> notes;
  for (double p : pgts) {
    const Group* ours = find_group(groups, kPaperClaims.ours, p);
    const Group* fr = find_group(groups, kPaperClaims.frontier, p);
    const Group* pre = find_group(groups, kPaperClaims.predefined, p);
    if (ours && fr && !ours->trials.empty() && !fr->trials.empty()) {
      const Stat a = over(*ours, paper_total), c = over(*fr, paper_total);
      notes.push_back("P_gt " + pgt_text(p) + ": " + ours->method.label + " vs " + fr->method.label + " total: " +
                      diff_text(a, c, 1.0, " s") + "; " +
                      (a.mean < c.mean ? "less than frontier, as in the paper (" + less + ")"
                                       : "NOT less than frontier: differs from the paper (" + less + ")") +
                      resolution(a, c) + ".");
    }
    if (pre && !pre->trials.empty())
      for (const Group* act : {ours, fr})
        if (act && !act->trials.empty()) {
          const Stat a = over(*act, paper_total), c = over(*pre, paper_total);
          notes.push_back("P_gt " + pgt_text(p) + ": " + act->method.label + " vs " + pre->method.label + " total: " +
                          diff_text(a, c, 1.0, " s") + "; " +
                          (a.mean > more_factor * c.mean ? "more than " + more + ", as in the paper"
                                                         : "NOT more than " + more + ": differs from the paper") +
                          resolution(a, c) + ".");
        }
  }
  b->items(notes);
}

// Section 4: stops, successful and attempted views and failed attempts per stop, by cause.
void views_section(const std::vector<Group>& groups, Blocks* b) {
  const int per_stop = kPaperClaims.predefined_views_per_stop + kPaperClaims.more_views_per_stop;
  b->heading(2, "4. Views and failures per stop");
  b->paragraph("Paper: every method executes the same number of successful views, " + std::to_string(per_stop) +
               " per stop (" + std::to_string(kPaperClaims.predefined_views_per_stop) + " predefined + " +
               std::to_string(kPaperClaims.more_views_per_stop) + " more), " + std::to_string(per_stop * kPaperClaims.stops) +
               " in all; it reports no failure counts, only that some best views are unreachable.");
  std::vector<Row> rows;
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
    rows.push_back({pgt_text(g.p_gt), g.method.label, pm(over(g, [](const TrialResult& t) { return double(t.stops); }), "%.0f"),
                    pm(over(g, [&](const TrialResult& t) { return per_stop_of(t.views_ok, t); }), "%.1f"),
                    pm(over(g, [&](const TrialResult& t) { return per_stop_of(t.views_attempted, t); }), "%.1f"),
                    by_cause.empty() ? std::string("none") : by_cause});
  }
  b->table({"P_gt", "method", "stops", "successful views / stop", "attempted / stop", "failed attempts / stop (by cause)"},
           rows);
}

// Section 5: the field's metrics at the end, one table per kind of metric.
void field_section(const std::vector<Group>& groups, const std::vector<std::string>& field, Blocks* b) {
  b->heading(2, "5. The field's metrics at the end");
  b->paragraph("Fruit detection (map clusters matched one-to-one to the true ripe fruits), shape errors of the matched "
               "fruits, fruit-level completeness, the voxel precision of the fruit class, and motion cost "
               "(docs/metrics.md). Mean ± std over the trials that have the figure (n); a centre or volume "
               "error needs a matched fruit. All of them per group in field.csv.");
  // One table per report group of the column table, in its order; then the time budgets.
  std::vector<std::pair<std::string, std::vector<std::string>>> all_tables;
  std::map<std::string, const char*> formats;
  for (const records::FieldInfo* c : records::final_figure_columns()) {
    const std::string title = records::report_group_title(c->field.final.group);
    if (all_tables.empty() || all_tables.back().first != title) all_tables.push_back({title, {}});
    all_tables.back().second.push_back(c->field.final.key);
    formats[c->field.final.key] = c->field.final.format;
  }
  std::vector<std::string> budget_keys;
  for (const std::string& k : field)
    if (k.rfind("sc_at_", 0) == 0) budget_keys.push_back(k);
  if (!budget_keys.empty()) all_tables.push_back({"Coverage reached by a simulated time budget", budget_keys});
  for (const auto& [title, keys] : all_tables) {
    b->paragraph(title, true);
    Row header = {"P_gt", "method"};
    header.insert(header.end(), keys.begin(), keys.end());
    std::vector<Row> rows;
    for (const Group& g : groups) {
      Row r = {pgt_text(g.p_gt), g.method.label};
      for (const std::string& k : keys) r.push_back(pm(field_stat(g, k), formats.count(k) ? formats.at(k) : "%.3f"));
      rows.push_back(r);
    }
    b->table(header, rows);
  }
}

// Section 6 (what tools/goal_check.py computed): on the worlds every method completed, SC after
// k views carried forward, each method against the better of frontier and global, and after 60
// views against half the way from that to the oracle.
void matched_worlds_section(const std::vector<Group>& groups, const std::vector<double>& pgts, Blocks* b) {
  b->heading(2, "6. Methods on the same worlds");
  b->paragraph("Each P_gt's worlds every method completed (an ok trial each): fruit SC after the 30th, 60th and 90th "
               "successful view (a trial that ended before keeps its last figure) and at the end, mean ± std over those "
               "worlds; each method held against the better of frontier and global and, after 60 views, against half the "
               "way from that to the oracle.");
  bool any = false;
  for (double p : pgts) {
    const MatchedWorlds mw = matched_worlds(groups, p);
    if (mw.worlds.empty()) continue;
    any = true;
    std::string list;
    for (const std::string& w : mw.worlds) list += (list.empty() ? "" : ", ") + w;
    b->paragraph("P_gt " + pgt_text(p) + ": " + std::to_string(mw.worlds.size()) + " worlds every method completed (" + list +
                 ")", true);
    std::vector<Row> rows;
    for (const MatchedWorlds::Method& m : mw.methods) {
      Row r = {m.label + (m.reads_truth ? " (reads the truth)" : "")};
      for (const Stat& s : m.sc) r.push_back(pm(s));
      r.push_back(num(m.views.mean, "%.1f"));
      rows.push_back(r);
    }
    b->table({"method", "SC after 30", "after 60", "after 90", "final", "successful views"}, rows);
    b->items(mw.checks);
  }
  if (!any) b->paragraph("None: no world has an ok trial of every method at one P_gt.");
}

// Section 7 (what tools/sc_per_view.py computed): the SC each successful view adds, by phase.
void per_view_section(const std::vector<Group>& groups, Blocks* b) {
  b->heading(2, "7. Coverage added per view, by phase");
  b->paragraph("The fruit SC the successful views of each phase added (the initial scans; the views after them), divided "
               "by their number, in thousandths of the fruit surface; mean ± std over the trials.");
  std::vector<Row> rows;
  for (const Group& g : groups) {
    const PerViewGain s = sc_per_view(g);
    rows.push_back({pgt_text(g.p_gt), g.method.label, pm(s.initial, "%.3g"), pm(s.later, "%.3g")});
  }
  b->table({"P_gt", "method", "SC added per initial-scan view (1e-3)", "SC added per later view (1e-3)"}, rows);
}

// The closing list of failed, missing and incomplete trials.
void problems_section(const MergedTrials& m, std::size_t failed, Blocks* b) {
  b->heading(2, "Failed, missing and incomplete trials");
  if (failed == 0 && m.missing.empty() && m.incomplete.empty()) b->paragraph("None.");
  std::vector<std::string> items;
  for (const TrialResult& t : m.trials)
    if (t.status != "ok") items.push_back("failed: " + t.spec.id + ": " + t.message);
  for (const std::string& id : m.missing) items.push_back("missing: " + id);
  for (const IncompleteFolder& i : m.incomplete)
    items.push_back("incomplete (ignored): " + fs::path(i.path).filename().string() + ": " + i.reason);
  b->items(items);
}

}  // namespace

MatchedWorlds matched_worlds(const std::vector<Group>& groups, double p_gt) {
  MatchedWorlds out;
  std::vector<const Group*> gs;
  for (const Group& g : groups)
    if (pgt_text(g.p_gt) == pgt_text(p_gt)) gs.push_back(&g);
  const auto world_of = [](const TrialResult& t) {
    return t.spec.world_seed ? std::to_string(*t.spec.world_seed) : std::string("file");
  };
  // The worlds with an ok trial of every method, in the first method's order.
  if (gs.empty()) return out;
  for (const TrialResult* t : gs.front()->trials) {
    const std::string w = world_of(*t);
    const bool everywhere = std::all_of(gs.begin(), gs.end(), [&](const Group* g) {
      return std::any_of(g->trials.begin(), g->trials.end(), [&](const TrialResult* u) { return world_of(*u) == w; });
    });
    if (everywhere && std::find(out.worlds.begin(), out.worlds.end(), w) == out.worlds.end()) out.worlds.push_back(w);
  }
  if (out.worlds.empty()) return out;
  const auto sc_after = [](const TrialResult& t, int k) {  // carried forward: the last figure of a shorter trial
    if (t.coverage.empty()) return 0.0;
    return t.coverage[std::min<std::size_t>(t.coverage.size(), static_cast<std::size_t>(k)) - 1];
  };
  for (const Group* g : gs) {
    MatchedWorlds::Method m;
    m.label = g->method.label;
    m.reads_truth = g->method.choice.name.rfind("oracle", 0) == 0;
    std::vector<std::vector<double>> v(kEqualViewCounts.size() + 1);
    std::vector<double> views;
    for (const std::string& w : out.worlds)
      for (const TrialResult* t : g->trials)
        if (world_of(*t) == w) {  // the first trial of the world (one per world in an experiment)
          for (std::size_t i = 0; i < kEqualViewCounts.size(); ++i) v[i].push_back(sc_after(*t, kEqualViewCounts[i]));
          v.back().push_back(t->coverage.empty() ? 0.0 : t->coverage.back());
          views.push_back(double(t->coverage.size()));
          break;
        }
    for (const auto& x : v) m.sc.push_back(stat(x));
    m.views = stat(views);
    out.methods.push_back(m);
  }
  // Each method against the better of the baselines at each count, and after 60 views against
  // half the way from that to the oracle.
  std::vector<const MatchedWorlds::Method*> base;
  const MatchedWorlds::Method* oracle = nullptr;
  for (const MatchedWorlds::Method& m : out.methods) {
    const std::string& name = gs[std::size_t(&m - out.methods.data())]->method.choice.name;
    if (name == kPaperClaims.frontier || name == "global") base.push_back(&m);
    if (name == "oracle") oracle = &m;
  }
  if (base.empty()) return out;
  std::string base_names;
  for (const auto* m : base) base_names += (base_names.empty() ? "" : " and ") + m->label;
  const char* names[] = {"30", "60", "90", "final"};
  for (const MatchedWorlds::Method& m : out.methods) {
    if (m.reads_truth || std::find(base.begin(), base.end(), &m) != base.end()) continue;
    std::string checks;
    for (std::size_t i = 0; i < m.sc.size(); ++i) {
      double best = 0.0;
      for (const auto* c : base) best = std::max(best, c->sc[i].mean);
      checks += std::string(i ? "; " : "") + "after " + names[i] + ": " + num(m.sc[i].mean, "%.3f") + " vs " + num(best, "%.3f") +
                (m.sc[i].mean >= best ? " ok" : " NOT met");
    }
    if (oracle) {
      double best60 = 0.0;
      for (const auto* c : base) best60 = std::max(best60, c->sc[1].mean);
      const double half = best60 + 0.5 * (oracle->sc[1].mean - best60);
      checks += "; half way to the oracle after 60: " + num(m.sc[1].mean, "%.3f") + " vs " + num(half, "%.3f") +
                (m.sc[1].mean >= half ? " ok" : " NOT met");
    }
    out.checks.push_back(m.label + " against the better of " + base_names + ": " + checks);
  }
  return out;
}

PerViewGain sc_per_view(const Group& g) {
  std::vector<double> initial, later;
  for (const TrialResult* t : g.trials) {
    double prev = 0.0, added[2] = {0.0, 0.0};
    int n[2] = {0, 0};
    for (std::size_t i = 0; i < t->coverage.size(); ++i) {
      const int k = i < t->phases.size() && t->phases[i] == records::to_string(records::ViewPhase::kInitial) ? 0 : 1;
      added[k] += t->coverage[i] - prev;
      ++n[k];
      prev = t->coverage[i];
    }
    if (n[0]) initial.push_back(1e3 * added[0] / n[0]);
    if (n[1]) later.push_back(1e3 * added[1] / n[1]);
  }
  return {stat(initial), stat(later)};
}

nlohmann::json findings_json(const MergedTrials& m, const std::vector<Group>& groups, const std::vector<std::string>& field) {
  std::size_t ok = 0, failed = 0;
  for (const TrialResult& t : m.trials) (t.status == "ok" ? ok : failed)++;
  const std::vector<double> pgts = p_gts_of(groups);
  Blocks b;
  findings_intro(m, ok, failed, &b);
  coverage_section(groups, pgts, field, &b);
  noise_section(groups, pgts, &b);
  runtime_section(groups, pgts, &b);
  views_section(groups, &b);
  field_section(groups, field, &b);
  matched_worlds_section(groups, pgts, &b);
  per_view_section(groups, &b);
  problems_section(m, failed, &b);
  return b.list;
}

}  // namespace canopy::experiments::report
