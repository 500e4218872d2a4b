// Charts as SVG text (svg_chart.h).

#include "canopy/common/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "canopy/common/value_text.h"

namespace canopy::svg {

namespace {

// Panel margins [px]: the y axis' labels left, the title above, the x axis' labels below.
constexpr double kLeft = 54.0, kRight = 12.0, kTop = 24.0, kBottom = 40.0, kBarBottom = 56.0;
constexpr double kFigureTitle = 22.0;
constexpr double kLegendWidth = 150.0;  // a bar chart's legend stands beside its plot area

std::string px(double v) { return format_number(v, "%.1f"); }

std::string esc(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

// A text element; '\n' starts a new line below.
std::string text(double x, double y, const std::string& s, const std::string& attrs = "") {
  std::string out = "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\"" + (attrs.empty() ? "" : " " + attrs) + ">";
  std::size_t start = 0;
  for (int line = 0;; ++line) {
    const std::size_t end = s.find('\n', start);
    const std::string part = s.substr(start, end == std::string::npos ? std::string::npos : end - start);
    out += line == 0 ? esc(part) : "<tspan x=\"" + px(x) + "\" dy=\"1.1em\">" + esc(part) + "</tspan>";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out + "</text>";
}

// Round tick values covering [lo, hi]: steps of 1, 2 or 5 times a power of ten, about five.
std::vector<double> ticks(double lo, double hi) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / 5.0, p = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / p < 1.5 ? p : raw / p < 3.5 ? 2 * p : raw / p < 7.5 ? 5 * p : 10 * p;
  std::vector<double> out;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step) out.push_back(std::fabs(t) < 1e-12 * step ? 0.0 : t);
  return out;
}

std::string tick_text(double v) { return format_number(v, "%g"); }

// The plot area of a panel placed at (ox, oy) and the data ranges it shows.
struct Area {
  double left, right, top, bottom;
  double xmin = 0.0, xmax = 1.0, ymin = 0.0, ymax = 1.0;
  double x(double v) const { return left + (xmax > xmin ? (v - xmin) / (xmax - xmin) : 0.5) * (right - left); }
  double y(double v) const { return bottom - (ymax > ymin ? (v - ymin) / (ymax - ymin) : 0.0) * (bottom - top); }
};

// The y range of a panel: from 0 (or below) to its data's top (or the fixed top), rounded to a tick.
void y_range(const Panel& p, double lo, double hi, Area* a) {
  a->ymin = std::min(p.y_min, lo);
  a->ymax = p.y_max > p.y_min ? p.y_max : std::max(hi, a->ymin + 1e-9);
  if (!(p.y_max > p.y_min)) {
    const std::vector<double> t = ticks(a->ymin, a->ymax);
    if (!t.empty() && t.back() < a->ymax) a->ymax += (t.size() > 1 ? t[1] - t[0] : 1.0) - (a->ymax - t.back());
  }
}

std::string axes(const Panel& p, const Area& a, bool x_ticks) {
  std::string s = "<line x1=\"" + px(a.left) + "\" y1=\"" + px(a.bottom) + "\" x2=\"" + px(a.right) + "\" y2=\"" +
                  px(a.bottom) + "\" stroke=\"#999\"/><line x1=\"" + px(a.left) + "\" y1=\"" + px(a.top) + "\" x2=\"" +
                  px(a.left) + "\" y2=\"" + px(a.bottom) + "\" stroke=\"#999\"/>";
  for (double t : ticks(a.ymin, a.ymax)) {
    s += "<line x1=\"" + px(a.left - 3) + "\" y1=\"" + px(a.y(t)) + "\" x2=\"" + px(a.right) + "\" y2=\"" + px(a.y(t)) +
         "\" stroke=\"#eee\"/>";
    s += text(a.left - 5, a.y(t) + 3.5, tick_text(t), "text-anchor=\"end\"");
  }
  if (x_ticks)
    for (double t : ticks(a.xmin, a.xmax))
      s += text(a.x(t), a.bottom + 13, tick_text(t), "text-anchor=\"middle\"");
  s += text((a.left + a.right) / 2, a.top - 8, p.title, "text-anchor=\"middle\" font-weight=\"bold\"");
  s += text((a.left + a.right) / 2, a.bottom + 30, p.x_label, "text-anchor=\"middle\"");
  s += text(12, (a.top + a.bottom) / 2, p.y_label,
            "text-anchor=\"middle\" transform=\"rotate(-90 12 " + px((a.top + a.bottom) / 2) + ")\"");
  return s;
}

// The legend's entries one below the other from the top of the plot area, starting at x (by
// default inside the area's top right corner).
std::string legend(const std::vector<std::pair<std::string, std::string>>& entries, const std::vector<bool>& dashed,
                   const Area& a, double x = -1.0) {
  if (x < 0.0) x = a.right - kLegendWidth;
  if (entries.empty()) return "";
  std::string s = "<g class=\"legend\">";
  double y = a.top + 10;
  for (std::size_t i = 0; i < entries.size(); ++i, y += 13) {
    s += "<line x1=\"" + px(x) + "\" y1=\"" + px(y - 3.5) + "\" x2=\"" + px(x + 18) + "\" y2=\"" + px(y - 3.5) +
         "\" stroke=\"" + entries[i].second + "\" stroke-width=\"2\"" + (dashed[i] ? " stroke-dasharray=\"5,3\"" : "") + "/>";
    s += text(x + 22, y, entries[i].first);
  }
  return s + "</g>";
}

std::string path_of(const std::vector<double>& xs, const std::vector<double>& ys, const Area& a) {
  std::string d;
  bool pen = false;
  for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
    if (!std::isfinite(ys[i])) {
      pen = false;
      continue;
    }
    d += (pen ? "L" : "M") + px(a.x(xs[i])) + "," + px(a.y(ys[i]));
    pen = true;
  }
  return d;
}

std::string lines_panel(const Panel& p, Area a) {
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
  for (const Series& s : p.series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      xlo = std::min(xlo, s.x[i]), xhi = std::max(xhi, s.x[i]);
      const double lo = i < s.lo.size() ? s.lo[i] : s.y[i], hi = i < s.hi.size() ? s.hi[i] : s.y[i];
      if (std::isfinite(lo)) ylo = std::min(ylo, lo);
      if (std::isfinite(hi)) yhi = std::max(yhi, hi);
    }
  for (const Mark& m : p.marks) {
    if (m.kind != Mark::Kind::kVertical) ylo = std::min(ylo, m.y), yhi = std::max(yhi, m.y);
    if (m.kind == Mark::Kind::kPoint) xlo = std::min(xlo, m.x), xhi = std::max(xhi, m.x);
  }
  if (!std::isfinite(xlo)) xlo = 0.0, xhi = 1.0;
  if (!std::isfinite(ylo)) ylo = 0.0, yhi = 1.0;
  a.xmin = xlo, a.xmax = xhi > xlo ? xhi : xlo + 1.0;
  y_range(p, ylo, yhi, &a);
  std::string s = "<g class=\"panel\" data-left=\"" + px(a.left) + "\" data-right=\"" + px(a.right) + "\" data-top=\"" +
                  px(a.top) + "\" data-bottom=\"" + px(a.bottom) + "\" data-xmin=\"" + tick_text(a.xmin) +
                  "\" data-xmax=\"" + tick_text(a.xmax) + "\">" + axes(p, a, true);
  std::vector<std::pair<std::string, std::string>> entries;
  std::vector<bool> dashed;
  for (std::size_t k = 0; k < p.series.size(); ++k) {
    const Series& r = p.series[k];
    const std::string colour = r.colour.empty() ? palette(k) : r.colour;
    if (!r.lo.empty() && r.lo.size() == r.y.size() && r.hi.size() == r.y.size()) {
      std::vector<double> bx = r.x, by = r.hi;
      bx.insert(bx.end(), r.x.rbegin(), r.x.rend());
      by.insert(by.end(), r.lo.rbegin(), r.lo.rend());
      s += "<path d=\"" + path_of(bx, by, a) + "Z\" fill=\"" + colour + "\" fill-opacity=\"0.12\" stroke=\"none\"/>";
    }
    s += "<path" + (r.id.empty() ? std::string() : " class=\"series\" data-id=\"" + esc(r.id) + "\"") + " d=\"" +
         path_of(r.x, r.y, a) + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + px(r.width) + "\"" +
         (r.dashed ? " stroke-dasharray=\"5,3\"" : "") + "/>";
    if (!r.label.empty()) entries.emplace_back(r.label, colour), dashed.push_back(r.dashed);
  }
  for (const Mark& m : p.marks) {
    const std::string dash = m.dashed ? " stroke-dasharray=\"4,3\"" : "";
    if (m.kind == Mark::Kind::kVertical)
      s += "<line x1=\"" + px(a.x(m.x)) + "\" y1=\"" + px(a.top) + "\" x2=\"" + px(a.x(m.x)) + "\" y2=\"" + px(a.bottom) +
           "\" stroke=\"" + m.colour + "\"" + dash + "/>";
    else if (m.kind == Mark::Kind::kHorizontal)
      s += "<line x1=\"" + px(a.left) + "\" y1=\"" + px(a.y(m.y)) + "\" x2=\"" + px(a.right) + "\" y2=\"" + px(a.y(m.y)) +
           "\" stroke=\"" + m.colour + "\"" + dash + "/>";
    else
      s += "<circle cx=\"" + px(a.x(m.x)) + "\" cy=\"" + px(a.y(m.y)) + "\" r=\"" + px(m.radius) + "\" fill=\"" + m.colour + "\"/>";
    if (!m.label.empty()) entries.emplace_back(m.label, m.colour), dashed.push_back(m.dashed);
  }
  if (p.legend) s += legend(entries, dashed, a);
  return s + "</g>";
}

std::string bars_panel(const Panel& p, Area a) {
  a.bottom += kBottom - kBarBottom;
  bool labelled_mark = false;
  for (const Mark& m : p.marks) labelled_mark |= m.kind == Mark::Kind::kHorizontal && !m.label.empty();
  const bool side_legend = p.legend && (!p.parts.empty() || labelled_mark);
  if (side_legend) a.right -= kLegendWidth;
  double hi = 0.0, lo = 0.0;
  for (const auto& row : p.values) {
    double sum = 0.0;
    for (double v : row) {
      if (!std::isfinite(v)) continue;
      sum += v;
      hi = std::max(hi, p.stacked ? sum : v);
      lo = std::min(lo, v);
    }
  }
  for (const Mark& m : p.marks)
    if (m.kind != Mark::Kind::kVertical) hi = std::max(hi, m.y);
  y_range(p, lo, hi, &a);
  const std::size_t n = std::max<std::size_t>(1, p.categories.size()), parts = std::max<std::size_t>(1, p.parts.size());
  a.xmin = 0.0, a.xmax = double(n);
  std::string s = "<g class=\"panel\">" + axes(p, a, false);
  const double slot = (a.right - a.left) / double(n);
  const auto colour = [&](std::size_t j) {
    return j < p.part_colours.size() && !p.part_colours[j].empty() ? p.part_colours[j] : palette(j);
  };
  for (std::size_t c = 0; c < p.values.size() && c < n; ++c) {
    double base = 0.0;
    for (std::size_t j = 0; j < p.values[c].size(); ++j) {
      const double v = std::isfinite(p.values[c][j]) ? p.values[c][j] : 0.0;
      double x0, w, y0, y1;
      if (p.stacked) {
        w = 0.6 * slot, x0 = a.left + (double(c) + 0.2) * slot, y0 = a.y(base + v), y1 = a.y(base);
        base += v;
      } else {
        w = 0.8 * slot / double(parts), x0 = a.left + (double(c) + 0.1) * slot + double(j) * w, y0 = a.y(std::max(v, 0.0)),
        y1 = a.y(std::min(v, 0.0));
      }
      s += "<rect x=\"" + px(x0) + "\" y=\"" + px(y0) + "\" width=\"" + px(w) + "\" height=\"" + px(std::max(0.0, y1 - y0)) +
           "\" fill=\"" + colour(j) + "\"/>";
    }
  }
  for (std::size_t c = 0; c < p.categories.size(); ++c)
    s += text(a.left + (double(c) + 0.5) * slot, a.bottom + 12, p.categories[c], "text-anchor=\"middle\" font-size=\"9\"");
  std::vector<std::pair<std::string, std::string>> entries;
  std::vector<bool> dashed;
  for (std::size_t j = 0; j < p.parts.size(); ++j) entries.emplace_back(p.parts[j], colour(j)), dashed.push_back(false);
  for (const Mark& m : p.marks) {
    if (m.kind != Mark::Kind::kHorizontal) continue;
    s += "<line x1=\"" + px(a.left) + "\" y1=\"" + px(a.y(m.y)) + "\" x2=\"" + px(a.right) + "\" y2=\"" + px(a.y(m.y)) +
         "\" stroke=\"" + m.colour + "\"" + (m.dashed ? " stroke-dasharray=\"4,3\"" : "") + "/>";
    if (!m.label.empty()) entries.emplace_back(m.label, m.colour), dashed.push_back(m.dashed);
  }
  if (side_legend) s += legend(entries, dashed, a, a.right + 8.0);
  return s + "</g>";
}

}  // namespace

std::string palette(std::size_t i) {
  static const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                  "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return colours[i % 10];
}

std::string render(const Figure& f) {
  const double top = f.title.empty() ? 0.0 : kFigureTitle;
  const std::size_t n = std::max<std::size_t>(1, f.panels.size());
  const double w = f.column ? f.panel_width : f.panel_width * double(n);
  const double h = top + (f.column ? f.panel_height * double(n) : f.panel_height);
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + px(w) + "\" height=\"" + px(h) + "\" viewBox=\"0 0 " +
                  px(w) + " " + px(h) + "\" font-family=\"sans-serif\" font-size=\"11\">";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>";
  if (!f.title.empty()) s += text(w / 2, 15, f.title, "text-anchor=\"middle\" font-size=\"12\"");
  for (std::size_t i = 0; i < f.panels.size(); ++i) {
    const double ox = f.column ? 0.0 : f.panel_width * double(i), oy = top + (f.column ? f.panel_height * double(i) : 0.0);
    Area a{ox + kLeft, ox + f.panel_width - kRight, oy + kTop, oy + f.panel_height - kBottom};
    const Panel& p = f.panels[i];
    s += p.kind == Panel::Kind::kLines ? lines_panel(p, a) : bars_panel(p, a);
  }
  return s + "</svg>\n";
}

}  // namespace canopy::svg
