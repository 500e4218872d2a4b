// Groups of an experiment's trials and the figures over them (report_groups.h).

#include "report_groups.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/value_text.h"

namespace canopy::experiments::report {

Stat stat(const std::vector<double>& v) { return sample_stats(v); }

std::string num(double x, const char* fmt) { return format_number(x, fmt); }
std::string pm(const Stat& s, const char* fmt) {
  if (s.n == 0) return "n/a";
  return num(s.mean, fmt) + " ± " + num(s.std, fmt) + " (n=" + std::to_string(s.n) + ")";
}

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

double category(const TrialResult& r, const records::PlotCategoryInfo& category) {
  double s = 0.0;
  for (const records::WallPhase p : category.phases) {
    const auto it = r.phase_s.find(to_string(p));
    if (it != r.phase_s.end()) s += it->second;
  }
  return s;
}

// The four phases of the paper's Fig. 4 (its "total run time").
double paper_total(const TrialResult& r) {
  double s = 0.0;
  for (const records::PlotCategoryInfo& c : records::plot_categories())
    if (c.paper) s += category(r, c);
  return s;
}

std::string pgt_text(double p) { return format_number(p, NumberFormat::kDigits6); }

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

double final_sc(const TrialResult& t) { return t.coverage.empty() ? 0.0 : t.coverage.back(); }
// A field metric over a group's trials that have it (finite).
Stat field_stat(const Group& g, const std::string& k) {
  std::vector<double> v;
  for (const TrialResult* t : g.trials) {
    const auto it = t->field.find(k);
    if (it != t->field.end() && std::isfinite(it->second)) v.push_back(it->second);
  }
  return stat(v);
}

}  // namespace canopy::experiments::report
