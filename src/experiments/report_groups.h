#pragma once
// Groups of an experiment's trials and the figures over them, shared by the report's tables
// (experiment_report.cpp) and its findings (experiment_findings.cpp). Internal to the library.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/stats.h"
#include "canopy/experiments/experiment_report.h"
#include "canopy/records/records.h"

namespace canopy::experiments::report {

using Stat = SampleStats;
Stat stat(const std::vector<double>& v);

std::string num(double x, const char* fmt = "%.6g");
// "mean ± std (n=N)", or "n/a" without trials.
std::string pm(const Stat& s, const char* fmt = "%.3f");

// A (method label, P_gt) group of ok trials, in the experiment's order.
struct Group {
  ExperimentMethod method;
  double p_gt = 1.0;
  std::vector<const TrialResult*> trials;
};

// The groups of the expected trials: methods in the experiment's order, then P_gt from high
// (no noise) to low; each with its ok trials.
std::vector<Group> groups_of(const MergedTrials& m);

// The seconds a trial spent in a plot category's phases.
double category(const TrialResult& r, const records::PlotCategoryInfo& category);
// The four phases of the paper's Fig. 4 (its "total run time").
double paper_total(const TrialResult& r);

template <typename F>
Stat over(const Group& g, F f) {
  std::vector<double> v;
  for (const TrialResult* r : g.trials) v.push_back(f(*r));
  return stat(v);
}

std::string pgt_text(double p);
// Difference of two group means with its standard error; relative to `base`.
std::string diff_text(const Stat& a, const Stat& base, double scale, const char* unit);
// " (within 2 standard errors: ...)" when the difference of the means is not resolved.
std::string resolution(const Stat& a, const Stat& b);
const Group* find_group(const std::vector<Group>& gs, const std::string& method, double p_gt);
double final_sc(const TrialResult& t);
// A field metric over a group's trials that have it (finite).
Stat field_stat(const Group& g, const std::string& k);

// The view counts the findings compare methods at (the 30th, 60th and 90th successful view).
inline const std::vector<int> kEqualViewCounts = {30, 60, 90};

// One P_gt's methods on the worlds every method completed (an ok trial each; what
// tools/goal_check.py computed): fruit SC after each of kEqualViewCounts (a trial that ended
// before keeps its last figure) and at the end, over those worlds.
struct MatchedWorlds {
  std::vector<std::string> worlds;  // world seeds ("file": the world file's own seed)
  struct Method {
    std::string label;
    bool reads_truth = false;       // an oracle
    std::vector<Stat> sc;           // after 30, 60, 90 views, final
    Stat views;                     // successful views
  };
  std::vector<Method> methods;      // in the groups' order
  // Per method other than the baselines (frontier, global) and the oracles: its SC against the
  // better baseline at each count and, with an oracle, after 60 views against half the way to it.
  std::vector<std::string> checks;
};
MatchedWorlds matched_worlds(const std::vector<Group>& groups, double p_gt);

// The fruit SC a group's successful views added per view, in thousandths, by phase: the initial
// scans and the views after them (what tools/sc_per_view.py computed); over the trials.
struct PerViewGain {
  Stat initial, later;
};
PerViewGain sc_per_view(const Group& g);

// The findings (the experiment held against the paper's findings, section by section) as
// blocks: experiment_report.h's ExperimentReport::findings.
nlohmann::json findings_json(const MergedTrials& m, const std::vector<Group>& groups, const std::vector<std::string>& field);

}  // namespace canopy::experiments::report
