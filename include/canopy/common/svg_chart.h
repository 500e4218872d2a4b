#pragma once
// canopy's one plot renderer: charts as SVG text, drawn in-process from a run's data (no
// plotting library, no child process; docs/report.md#figures). A figure is panels side by side or
// stacked, each a line chart (series with optional mean ± std bands, dashed or solid, vertical
// and horizontal marks, points) or a bar chart (stacked or grouped bars), written as a file of the
// run folder (sc_entropy.svg, fig3_entropy_coverage.svg, ...; jobs/figures.h). Each line panel's
// <g class="panel"> carries its plot area and x range as data attributes (data-left, data-right,
// data-top, data-bottom, data-xmin, data-xmax), so a page can map a cursor to data. Same data,
// same bytes.

#include <string>
#include <vector>

namespace canopy::svg {

/// One line of a line chart (x and y of equal length; lo and hi empty or of the same length:
/// the band drawn behind it).
struct Series {
  std::string label{};            ///< The legend's text ("" leaves it out of the legend).
  std::vector<double> x{}, y{};
  std::vector<double> lo{}, hi{};
  std::string colour{};           ///< "#rrggbb"; "" takes the palette's next.
  bool dashed = false;
  double width = 1.5;
  std::string id{};               ///< data-id of its path (the page finds a trial's line by it).
};

/// A mark across a panel: a vertical line at x, a horizontal line at y, or a point.
struct Mark {
  enum class Kind { kVertical, kHorizontal, kPoint } kind = Kind::kVertical;
  double x = 0.0, y = 0.0;
  std::string label{};            ///< Legend text of a horizontal line or a point ("" for none).
  std::string colour = "#cccccc";
  bool dashed = false;
  double radius = 4.0;            ///< A point's [px].
};

/// One panel.
struct Panel {
  enum class Kind { kLines, kBars } kind = Kind::kLines;
  std::string title{}, x_label{}, y_label{};
  double y_min = 0.0;             ///< Axes start at 0 unless the data go below.
  double y_max = 0.0;             ///< Fixed top when > y_min (a share: 1); else the data's.
  bool legend = true;
  // Lines.
  std::vector<Series> series{};
  std::vector<Mark> marks{};
  // Bars: one bar (stacked) or one group of bars per category, one value per part.
  std::vector<std::string> categories{};       ///< The x labels.
  std::vector<std::string> parts{};            ///< The stack's (or group's) legend names.
  std::vector<std::string> part_colours{};     ///< "" or empty: the palette.
  std::vector<std::vector<double>> values{};   ///< [category][part].
  bool stacked = true;                         ///< False: the parts side by side in each category.
};

/// A figure: its panels in a row (or a column), each panel_width x panel_height pixels.
struct Figure {
  std::string title{};
  std::vector<Panel> panels{};
  int panel_width = 420, panel_height = 260;
  bool column = false;            ///< Panels one above the other.
};

/// The palette's colour i ("#1f77b4", "#ff7f0e", ...; ten, then again).
std::string palette(std::size_t i);

/// The figure as an SVG document (UTF-8, no external references).
std::string render(const Figure& figure);

}  // namespace canopy::svg
