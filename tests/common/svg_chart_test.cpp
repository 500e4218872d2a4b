// The SVG chart renderer (svg_chart.h): the plot area maps data to pixels as its data
// attributes say, bars stack, legends name the series, text is escaped, and the output is
// deterministic.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "canopy/common/svg_chart.h"

namespace canopy::svg {
namespace {

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// The value of the first name="..." in s (std::regex is avoided: GCC 12 warns inside it at -O1).
std::string attr_text(const std::string& s, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t p = s.find(key);
  if (p == std::string::npos) return "";
  const std::size_t begin = p + key.size();
  return s.substr(begin, s.find('"', begin) - begin);
}

double attr(const std::string& s, const std::string& name) {
  const std::string v = attr_text(s, name);
  return v.empty() ? std::nan("") : std::stod(v);
}

// Every tag that starts with `open` (e.g. "<rect "), up to its closing '>'.
std::vector<std::string> tags(const std::string& s, const std::string& open) {
  std::vector<std::string> out;
  for (std::size_t p = s.find(open); p != std::string::npos; p = s.find(open, p + 1))
    out.push_back(s.substr(p, s.find('>', p) - p));
  return out;
}

TEST(SvgChart, ALineMapsItsEndsToThePlotAreaCorners) {
  Panel p;
  p.title = "t";
  p.y_max = 1.0;  // a share: 0..1
  Series line;
  line.x = {1.0, 3.0};
  line.y = {0.0, 1.0};
  line.colour = "#123456";
  p.series = {line};
  Figure f;
  f.panels = {p};
  const std::string s = render(f);
  EXPECT_EQ(s.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_EQ(s.substr(s.size() - 7), "</svg>\n");
  const double left = attr(s, "data-left"), right = attr(s, "data-right"), top = attr(s, "data-top"),
               bottom = attr(s, "data-bottom");
  EXPECT_EQ(attr(s, "data-xmin"), 1.0);
  EXPECT_EQ(attr(s, "data-xmax"), 3.0);
  // The first point at the bottom left corner, the last at the top right.
  char expected[96];
  std::snprintf(expected, sizeof expected, "d=\"M%.1f,%.1fL%.1f,%.1f\"", left, bottom, right, top);
  EXPECT_NE(s.find(expected), std::string::npos) << expected << "\n" << s;
  EXPECT_NE(s.find("stroke=\"#123456\""), std::string::npos);
  EXPECT_EQ(render(f), s);  // deterministic
}

TEST(SvgChart, AGapInTheDataLiftsThePen) {
  Panel p;
  Series line;
  line.x = {0, 1, 2, 3};
  line.y = {1, std::nan(""), 2, 3};
  p.series = {line};
  Figure f;
  f.panels = {p};
  const std::string s = render(f);
  std::string d;
  for (const std::string& tag : tags(s, "<path d=\""))
    if (tag.find("\" fill=\"none\"") != std::string::npos) d = attr_text(tag, "d");
  ASSERT_FALSE(d.empty()) << s;
  EXPECT_EQ(count(d, "M"), 2) << d;
  EXPECT_EQ(count(d, "L"), 1) << d;
}

TEST(SvgChart, StackedBarsSumToTheirTotalAndGroupedBarsStandSideBySide) {
  Panel p;
  p.kind = Panel::Kind::kBars;
  p.categories = {"a", "b"};
  p.parts = {"x", "y"};
  p.values = {{1.0, 2.0}, {3.0, 1.0}};
  p.y_max = 4.0;
  Figure f;
  f.panels = {p};
  std::string s = render(f);
  EXPECT_EQ(count(s, "<rect x="), 4);
  // Category b's bars: 3 then 1 on top of it reach the top (4 of 4) exactly.
  std::vector<double> ys, hs;
  for (const std::string& tag : tags(s, "<rect x="))
    ys.push_back(attr(tag, "y")), hs.push_back(attr(tag, "height"));
  ASSERT_EQ(ys.size(), 4u);
  EXPECT_NEAR(hs[2], 3.0 * hs[3], 0.2);         // 3 and 1
  EXPECT_NEAR(ys[2], ys[3] + hs[3], 0.1);        // stacked: the second on top of the first
  EXPECT_NEAR(hs[0] + hs[1], hs[2], 0.2);        // a: 1 + 2 = 3, b's first part
  p.stacked = false;
  f.panels = {p};
  s = render(f);
  ys.clear();
  std::vector<double> xs;
  for (const std::string& tag : tags(s, "<rect x=")) xs.push_back(attr(tag, "x"));
  ASSERT_EQ(xs.size(), 4u);
  EXPECT_LT(xs[0], xs[1]);  // side by side
  EXPECT_LT(xs[1], xs[2]);
}

TEST(SvgChart, LegendsNameTheSeriesAndTextIsEscaped) {
  Panel p;
  Series a, b;
  a.label = "ours & <frontier>";
  a.x = b.x = {0, 1};
  a.y = b.y = {0, 1};
  b.dashed = true;
  b.label = "noisy";
  p.series = {a, b};
  Figure f;
  f.title = "P_gt \"1\"";
  f.panels = {p};
  const std::string s = render(f);
  EXPECT_NE(s.find("ours &amp; &lt;frontier&gt;"), std::string::npos);
  EXPECT_NE(s.find("P_gt &quot;1&quot;"), std::string::npos);
  EXPECT_NE(s.find(">noisy</text>"), std::string::npos);
  EXPECT_EQ(s.find("<frontier>"), std::string::npos);
  EXPECT_NE(s.find("stroke=\"" + palette(1) + "\" stroke-width=\"1.5\" stroke-dasharray"), std::string::npos);
  p.legend = false;
  f.panels = {p};
  EXPECT_EQ(render(f).find("class=\"legend\""), std::string::npos);
}

TEST(SvgChart, PanelsInAColumnStackTheFigure) {
  Panel p;
  Figure f;
  f.panels = {p, p, p};
  f.column = true;
  f.panel_width = 100;
  f.panel_height = 50;
  const std::string s = render(f);
  EXPECT_NE(s.find("width=\"100.0\" height=\"150.0\""), std::string::npos) << s.substr(0, 200);
  f.column = false;
  EXPECT_NE(render(f).find("width=\"300.0\" height=\"50.0\""), std::string::npos);
  EXPECT_EQ(palette(0), palette(10));
}

}  // namespace
}  // namespace canopy::svg
