// The figures of canopy's commands as SVG (figures.h).

#include "canopy/jobs/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "canopy/common/atomic_file.h"
#include "canopy/common/csv.h"
#include "canopy/common/enum_names.h"
#include "canopy/common/svg_chart.h"
#include "canopy/common/value_text.h"
#include "canopy/records/records.h"

namespace canopy::jobs {

namespace {

using svg::Figure;
using svg::Mark;
using svg::Panel;
using svg::Series;

// A CSV table read back: its rows as maps from column name to field.
std::vector<std::map<std::string, std::string>> table(const std::string& text) {
  const std::vector<std::vector<std::string>> rows = split_csv(text);
  std::vector<std::map<std::string, std::string>> out;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < rows[0].size() && c < rows[r].size(); ++c) row[rows[0][c]] = rows[r][c];
    out.push_back(std::move(row));
  }
  return out;
}

double number(const std::map<std::string, std::string>& row, const std::string& key) {
  const auto it = row.find(key);
  if (it == row.end() || it->second.empty()) return std::nan("");
  return c_stod(it->second);
}

std::string hex(const Rgb8& c) {
  char b[8];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", c.r, c.g, c.b);
  return b;
}

std::string text_of(const nlohmann::json& j) {
  return j.is_number() ? format_number(j.get<double>(), "%g") : j.is_string() ? j.get<std::string>() : j.dump();
}

// A mean curve with its ± std band.
Series band(const std::string& label, const std::vector<double>& x, const std::vector<double>& mean,
            const std::vector<double>& std, const std::string& colour, bool dashed) {
  Series s{label, x, mean, {}, {}, colour, dashed};
  for (std::size_t i = 0; i < mean.size(); ++i) {
    s.lo.push_back(mean[i] - std[i]);
    s.hi.push_back(mean[i] + std[i]);
  }
  return s;
}

// Groups of rows by (label, P_gt), in the order of the labels and from high to low P_gt: the
// report's colours (one per label) and line styles (solid: the highest P_gt, no noise).
struct Groups {
  std::vector<std::string> labels;
  std::vector<double> pgts;  // high to low
  explicit Groups(const std::vector<std::map<std::string, std::string>>& rows) {
    for (const auto& r : rows) {
      if (std::find(labels.begin(), labels.end(), r.at("label")) == labels.end()) labels.push_back(r.at("label"));
      const double p = number(r, "p_gt");
      if (std::find(pgts.begin(), pgts.end(), p) == pgts.end()) pgts.push_back(p);
    }
    std::sort(pgts.rbegin(), pgts.rend());
  }
  std::string colour(const std::string& label) const {
    return svg::palette(std::size_t(std::find(labels.begin(), labels.end(), label) - labels.begin()));
  }
};

Figures fig3(const experiments::ExperimentReport& rep, const Groups& g) {
  const auto curves = table(rep.curves_csv);
  Panel h{Panel::Kind::kLines, "Fruit entropy", "successful views", "total fruit entropy [nats]"};
  Panel sc{Panel::Kind::kLines, "Fruit surface coverage", "successful views", "fruit surface coverage"};
  sc.y_max = 1.0;
  int trials = 0;
  for (const std::string& label : g.labels)
    for (const double p : g.pgts) {
      std::vector<double> v, hm, hs, cm, cs;
      for (const auto& r : curves)
        if (r.at("label") == label && number(r, "p_gt") == p) {
          v.push_back(number(r, "view"));
          hm.push_back(number(r, "entropy_mean")), hs.push_back(number(r, "entropy_std"));
          cm.push_back(number(r, "sc_mean")), cs.push_back(number(r, "sc_std"));
          trials = std::max(trials, int(number(r, "trials")));
        }
      if (v.empty()) continue;
      const std::string name = label + ", P_gt " + format_number(p, "%g");
      h.series.push_back(band(name, v, hm, hs, g.colour(label), p != g.pgts.front()));
      sc.series.push_back(band(name, v, cm, cs, g.colour(label), p != g.pgts.front()));
    }
  h.legend = false;
  Figure f{"Entropy and surface coverage, mean ± std over up to " + std::to_string(trials) +
               " trials (solid: no noise, dashed: segmentation noise)",
           {h, sc}, 460, 320};
  return {{"fig3_entropy_coverage.svg", svg::render(f)}};
}

Figures field_curves(const experiments::ExperimentReport& rep, const Groups& g) {
  const auto rows = table(rep.field_curves_csv);
  std::vector<std::string> metrics;
  for (const auto& r : rows)
    if (std::find(metrics.begin(), metrics.end(), r.at("metric")) == metrics.end()) metrics.push_back(r.at("metric"));
  if (metrics.empty()) return {};
  Figure f{"The field's metrics after each view, mean ± std over trials (solid: no noise, dashed: segmentation noise)",
           {}, 360, 300};
  for (const std::string& metric : metrics) {
    Panel panel{Panel::Kind::kLines, metric, "successful views", metric};
    for (const std::string& label : g.labels)
      for (const double p : g.pgts) {
        std::vector<double> v, m, s;
        for (const auto& r : rows)
          if (r.at("label") == label && number(r, "p_gt") == p && r.at("metric") == metric)
            v.push_back(number(r, "view")), m.push_back(number(r, "mean")), s.push_back(number(r, "std"));
        if (!v.empty())
          panel.series.push_back(band(label + ", P_gt " + format_number(p, "%g"), v, m, s, g.colour(label), p != g.pgts.front()));
      }
    panel.legend = f.panels.empty();
    f.panels.push_back(panel);
  }
  return {{"field_curves.svg", svg::render(f)}};
}

Figures fig4(const experiments::ExperimentReport& rep) {
  Panel bars{Panel::Kind::kBars, "Run time split (mean over trials)", "", "wall time per mission [s]"};
  const auto rows = table(rep.runtime_csv);
  std::vector<const records::PlotCategoryInfo*> paper;
  for (const records::PlotCategoryInfo& c : records::plot_categories())
    if (c.paper) paper.push_back(&c), bars.parts.push_back(c.title);
  for (const auto& r : rows) {
    bars.categories.push_back(r.at("label") + "\nP_gt " + format_number(number(r, "p_gt"), "%g") + "\n(n=" + r.at("trials") + ")");
    std::vector<double> v;
    for (const records::PlotCategoryInfo* c : paper) v.push_back(number(r, std::string(to_string(c->category)) + "_s_mean"));
    bars.values.push_back(v);
  }
  Figure f{"", {bars}, std::max(360, 120 + 110 * int(rows.size())), 340};
  return {{"fig4_runtime.svg", svg::render(f)}};
}

Figures gain_truth(const experiments::ExperimentReport& rep) {
  if (rep.gain_truth_csv.empty()) return {};
  const auto rows = table(rep.gain_truth_csv);
  std::vector<std::pair<std::string, std::string>> groups;  // (label, p_gt)
  std::vector<std::string> scores;
  for (const auto& r : rows) {
    const std::pair<std::string, std::string> g{r.at("label"), r.at("p_gt")};
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
    if (std::find(scores.begin(), scores.end(), r.at("score")) == scores.end()) scores.push_back(r.at("score"));
  }
  Figure f{"Every gain against the ground truth (oracle) on the candidates of the planning rounds", {}, 520, 340};
  const std::pair<const char*, const char*> metrics[] = {{"spearman", "Spearman ρ with the truth (mean over rounds)"},
                                                         {"top1", "top view = truth's top-1"},
                                                         {"top5", "top view in truth's top-5"}};
  for (const auto& [key, title] : metrics) {
    Panel p{Panel::Kind::kBars, title, "", key};
    p.stacked = false;
    p.categories = scores;
    for (const auto& g : groups) p.parts.push_back(g.first + " P_gt " + g.second);
    for (const std::string& score : scores) {
      std::vector<double> v;
      for (const auto& g : groups) {
        double x = std::nan("");
        for (const auto& r : rows)
          if (r.at("label") == g.first && r.at("p_gt") == g.second && r.at("score") == score) x = number(r, key);
        v.push_back(x);
      }
      p.values.push_back(v);
    }
    p.legend = f.panels.empty();
    f.panels.push_back(p);
  }
  return {{"gain_truth.svg", svg::render(f)}};
}

}  // namespace

Figures mission_figures(const nlohmann::json& d, const nlohmann::json& wall) {
  const nlohmann::json& v = d.at("views");
  const nlohmann::json& s = d.value("summary", nlohmann::json::object());
  const std::string method = s.value("method", nlohmann::json::object()).value("name", std::string("?"));
  Panel sc{Panel::Kind::kLines, "", "", "fruit surface coverage"};
  Panel h{Panel::Kind::kLines, "", "successful views", "fruit entropy [nats]"};
  sc.y_max = 1.0;
  h.legend = false;
  Series c{"", {}, {}, {}, {}, "#d62728"}, e{"", {}, {}, {}, {}, "#1f77b4"};
  nlohmann::json last_stop;
  std::vector<records::ViewPhase> phases_seen;
  for (std::size_t i = 0; i < v.at("attempt").size(); ++i) {
    if (!v.at("success")[i].get<bool>()) continue;
    const double n = v.at("successful_views")[i].get<double>();
    if (!last_stop.is_null() && v.at("stop")[i] != last_stop)
      for (Panel* p : {&sc, &h}) p->marks.push_back({Mark::Kind::kVertical, n - 0.5});
    last_stop = v.at("stop")[i];
    c.x.push_back(n), c.y.push_back(v.at("coverage")[i].is_number() ? v.at("coverage")[i].get<double>() : std::nan(""));
    // Each view a dot in its phase's colour (records::view_colour: the report's and the bags' too).
    const records::ViewPhase* phase = v.contains("phase") ? find_enum(records::kViewPhaseNames, v.at("phase")[i].get<std::string>()) : nullptr;
    if (phase && std::isfinite(c.y.back())) {
      const bool first = std::find(phases_seen.begin(), phases_seen.end(), *phase) == phases_seen.end();
      if (first) phases_seen.push_back(*phase);
      sc.marks.push_back({Mark::Kind::kPoint, n, c.y.back(), first ? records::view_phase_legend(*phase) : "",
                          hex(records::view_colour(*phase, true)), false, 2.5});
    }
    e.x.push_back(n), e.y.push_back(v.at("entropy")[i].is_number() ? v.at("entropy")[i].get<double>() : std::nan(""));
  }
  sc.series = {c};
  h.series = {e};
  Figure curves{"canopy " + d.value("kind", std::string("mission")) + " (" + method + ", P_gt " +
                    text_of(s.value("p_gt", nlohmann::json())) + ", seed " + text_of(s.value("seed", nlohmann::json())) + ")",
                {sc, h}, 420, 170, true};
  Figures out = {{"sc_entropy.svg", svg::render(curves)}};
  if (wall.contains("phases_s")) {
    Panel bars{Panel::Kind::kBars, "", "", "wall time [s]"};
    bars.categories = {method};
    std::vector<double> values;
    for (const records::PlotCategoryInfo& cat : records::plot_categories()) {
      double t = 0.0;
      for (const records::WallPhase p : cat.phases) t += wall["phases_s"].value(to_string(p), 0.0);
      bars.parts.push_back(std::string(cat.title) + " (" + format_number(t, "%.1f") + " s)");
      values.push_back(t);
    }
    bars.values = {values};
    out["runtime.svg"] = svg::render(Figure{"run time split (" + format_number(s.value("simulated_time_s", 0.0), "%.0f") +
                                                " s simulated)",
                                            {bars}, 420, 320});
  }
  return out;
}

Figures experiment_figures(const experiments::ExperimentReport& rep) {
  const Groups g(table(rep.runtime_csv));
  Figures out = fig3(rep, g);
  for (Figures more : {field_curves(rep, g), fig4(rep), gain_truth(rep)}) out.insert(more.begin(), more.end());
  return out;
}

Figures ablation_figures(const std::string& summary_csv) {
  const auto rows = table(summary_csv);
  if (rows.empty()) return {};
  using Key = std::tuple<std::string, std::string, double>;  // gain, rays, P_gt
  std::vector<Key> keys;
  for (const auto& r : rows) {
    const Key k{r.at("gain"), r.at("rays"), number(r, "p_gt")};
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  const bool ours = std::any_of(keys.begin(), keys.end(), [](const Key& k) { return std::get<1>(k) == "ours"; });
  const std::string rays_main = ours ? "ours" : std::get<1>(keys.front());
  // OSAMCEP may run in several variants ("osamcep-per_voxel", ...): the ray-set plot shows each.
  std::vector<Key> osamcep, by_gain, by_rays;
  for (const Key& k : keys)
    if (std::get<0>(k).rfind("osamcep", 0) == 0) osamcep.push_back(k);
  const std::string gain_main = osamcep.empty() ? std::get<0>(keys.front()) : "osamcep";
  for (const Key& k : keys) {
    if (std::get<1>(k) == rays_main) by_gain.push_back(k);
    if (osamcep.empty() && std::get<0>(k) == gain_main) by_rays.push_back(k);
  }
  if (!osamcep.empty()) by_rays = osamcep;
  const auto figure = [&](const std::vector<Key>& ks, bool gains, const std::string& title) {
    const auto label_of = [&](const Key& k) {
      if (gains) return std::get<0>(k);
      return std::get<0>(k) == gain_main ? std::get<1>(k) : std::get<1>(k) + " (" + std::get<0>(k) + ")";
    };
    std::vector<Key> sorted = ks;
    std::stable_sort(sorted.begin(), sorted.end(), [&](const Key& a, const Key& b) {
      return std::make_pair(label_of(a), -std::get<2>(a)) < std::make_pair(label_of(b), -std::get<2>(b));
    });
    std::vector<std::string> labels;
    Panel h{Panel::Kind::kLines, "", "views per plant", "fruit entropy per plant [nats]"};
    Panel c{Panel::Kind::kLines, "", "views per plant", "fruit surface coverage"};
    h.legend = false;
    c.marks.push_back({Mark::Kind::kHorizontal, 0.0, 0.8, "", "#999999"});
    for (const Key& k : sorted) {
      const std::string label = label_of(k);
      if (std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
      const std::string colour = svg::palette(std::size_t(std::find(labels.begin(), labels.end(), label) - labels.begin()));
      std::vector<double> v, hm, hs, cm, cs;
      for (const auto& r : rows)
        if (Key{r.at("gain"), r.at("rays"), number(r, "p_gt")} == k) {
          v.push_back(number(r, "view"));
          hm.push_back(number(r, "entropy_mean")), hs.push_back(number(r, "entropy_std"));
          cm.push_back(number(r, "coverage_mean")), cs.push_back(number(r, "coverage_std"));
        }
      const std::string name = label + " (P_gt " + format_number(std::get<2>(k), "%g") + ")";
      h.series.push_back(band(name, v, hm, hs, colour, std::get<2>(k) < 1.0));
      c.series.push_back(band(name, v, cm, cs, colour, std::get<2>(k) < 1.0));
    }
    return svg::render(Figure{title, {h, c}, 460, 320});
  };
  return {{"gains.svg", figure(by_gain, true, "Information gain metrics (rays: " + rays_main + ")")},
          {"rays.svg", figure(by_rays, false, "Ray sets (" + gain_main + ")")}};
}

Figures visibility_figures(const VisibilitySummary& s, const std::string& world_name) {
  if (s.results.empty()) return {};
  const evaluation::VisibilityParams& params = s.results.front().params;
  Panel per{Panel::Kind::kBars, "per camera position", "", "fruit detectability [%]"};
  Panel best{Panel::Kind::kLines, "best combination of k positions", "positions combined (k, best combination)",
             "fruit detectability [%]"};
  per.stacked = false;
  per.y_max = best.y_max = 100.0;
  for (const auto& p : params.positions) per.categories.push_back(p.name);
  per.values.assign(params.positions.size(), {});
  for (std::size_t i = 0; i < s.results.size(); ++i) {
    const bool all = s.labels[i] == "all";
    per.parts.push_back(all ? "all seeds" : "seed " + s.labels[i]);
    per.part_colours.push_back(all ? "#000000" : svg::palette(i));
    for (std::size_t p = 0; p < params.positions.size(); ++p)
      per.values[p].push_back(100.0 * s.results[i].detectability[p]);
    Series line{all ? "all seeds (one combination)" : "seed " + s.labels[i], {}, {}, {}, {},
                all ? "#000000" : svg::palette(i), false, all ? 2.0 : 1.0};
    for (const auto& b : s.results[i].best) line.x.push_back(b.k), line.y.push_back(100.0 * b.detectability);
    best.series.push_back(line);
  }
  per.marks.push_back({Mark::Kind::kHorizontal, 0.0, 69.0, "Hemming et al., best: 69 %", "#d62728", true});
  best.marks.push_back({Mark::Kind::kPoint, 1.0, 69.0, "Hemming et al. (k = 1, 5)", "#d62728"});
  best.marks.push_back({Mark::Kind::kPoint, 5.0, 90.0, "", "#d62728"});
  Figure f{"Fruit detectability (at most " + format_number(100.0 * params.max_occlusion, "%g") +
               " % of the camera-facing surface hidden), world '" + world_name + "'",
           {per, best}, 560, 380};
  return {{"visibility.svg", svg::render(f)}};
}

void write_figures(const std::string& dir, const Figures& figures) {
  const std::string d = dir.empty() || dir.back() == '/' ? dir : dir + "/";
  for (const auto& [name, text] : figures) write_file_atomic(d + name, text);
}

}  // namespace canopy::jobs
