// The commands' figures (figures.h), drawn from hand-made report data and tables: which files,
// what each one shows (the stops marked, the run time's parts named with their sums, one line
// per group), and nothing drawn from data that are not there.

#include <gtest/gtest.h>

#include <string>

#include "canopy/jobs/figures.h"

namespace canopy::jobs {
namespace {

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// Five attempts over two stops; the third failed.
nlohmann::json mission_data() {
  return nlohmann::json::parse(R"({
    "kind": "mission",
    "summary": {"method": {"name": "ours"}, "p_gt": 1, "seed": 7, "simulated_time_s": 42},
    "views": {"attempt": [1, 2, 3, 4, 5], "success": [true, true, false, true, true],
              "successful_views": [1, 2, 2, 3, 4], "stop": [0, 0, 0, 1, 1],
              "phase": ["initial", "initial", "nbv", "initial", "nbv"],
              "coverage": [0.1, 0.2, null, 0.3, 0.4], "entropy": [9, 8, null, 7, 6]}})");
}

TEST(Figures, AMissionDrawsItsCurvesWithTheStopsMarkedAndItsRunTimeByCategory) {
  const nlohmann::json wall = nlohmann::json::parse(
      R"({"wall_time_s": 10, "phases_s": {"mapping": 1.5, "clustering": 0.25, "scoring": 0.75, "control": 2}})");
  const Figures f = mission_figures(mission_data(), wall);
  ASSERT_EQ(f.size(), 2u);
  const std::string& curves = f.at("sc_entropy.svg");
  EXPECT_NE(curves.find("canopy mission (ours, P_gt 1, seed 7)"), std::string::npos);
  // The stop change (between successful views 2 and 3) marked in both panels.
  EXPECT_EQ(count(curves, "stroke=\"#cccccc\"/>"), 2) << curves;
  // Four successful views: four points per curve (M + 3 L).
  EXPECT_EQ(count(curves, "stroke=\"#d62728\" stroke-width"), 1);
  const std::size_t p = curves.find("<path d=\"M");
  ASSERT_NE(p, std::string::npos);
  EXPECT_EQ(count(curves.substr(p, curves.find('"', p + 9) - p), "L"), 3);
  // Each successful view a dot in its phase's colour (the report's and the bags' table), each
  // phase named once in the legend.
  EXPECT_EQ(count(curves, "<circle"), 4);
  EXPECT_EQ(count(curves, "r=\"2.5\" fill=\"" + std::string("#8e44ad") + "\""), 3);  // records' initial-scan colour
  EXPECT_EQ(count(curves, ">initial scan</text>"), 1);
  EXPECT_EQ(count(curves, ">next-best view</text>"), 1);
  const std::string& runtime = f.at("runtime.svg");
  // NBV planning sums its phases (clustering + scoring = 1 s); every plot category is a part.
  EXPECT_NE(runtime.find("NBV planning (1.0 s)"), std::string::npos) << runtime;
  EXPECT_NE(runtime.find("mapping (1.5 s)"), std::string::npos);
  EXPECT_NE(runtime.find("rendering (0.0 s)"), std::string::npos);
  EXPECT_NE(runtime.find("42 s simulated"), std::string::npos);
  // Without wall times by phase: no run-time figure.
  EXPECT_EQ(mission_figures(mission_data(), nlohmann::json::object()).count("runtime.svg"), 0u);
}

TEST(Figures, AnExperimentDrawsOneLinePerGroupAndItsRunTimeBars) {
  experiments::ExperimentReport rep;
  rep.curves_csv =
      "method,label,p_gt,view,trials,sc_mean,sc_std,entropy_mean,entropy_std\n"
      "ours,ours,1,1,2,0.1,0.01,9,1\nours,ours,1,2,2,0.2,0.01,8,1\n"
      "frontier,frontier,1,1,2,0.15,0.01,9,1\nfrontier,frontier,0.7,1,2,0.05,0.01,9,1\n";
  rep.runtime_csv = "method,label,p_gt,trials,mapping_s_mean,nbv_planning_s_mean,motion_planning_s_mean,control_s_mean\n"
                    "ours,ours,1,2,1,2,3,4\nfrontier,frontier,1,2,1,1,1,1\nfrontier,frontier,0.7,2,1,1,1,1\n";
  const Figures f = experiment_figures(rep);
  EXPECT_EQ(f.count("fig3_entropy_coverage.svg"), 1u);
  EXPECT_EQ(f.count("fig4_runtime.svg"), 1u);
  EXPECT_EQ(f.count("gain_truth.svg"), 0u);    // no candidates recorded
  EXPECT_EQ(f.count("field_curves.svg"), 0u);  // no field curves
  const std::string& fig3 = f.at("fig3_entropy_coverage.svg");
  EXPECT_NE(fig3.find("over up to 2 trials"), std::string::npos);
  // Three groups, two panels: six lines, each with its band; the noisy one dashed.
  EXPECT_EQ(count(fig3, "fill=\"none\" stroke="), 6);
  EXPECT_EQ(count(fig3, "fill-opacity=\"0.12\""), 6);
  EXPECT_EQ(count(fig3, "stroke-width=\"1.5\" stroke-dasharray"), 2);  // the lines (the legend has one more)
  EXPECT_EQ(count(fig3, "stroke-width=\"2\" stroke-dasharray"), 1);
  EXPECT_NE(fig3.find("frontier, P_gt 0.7"), std::string::npos);
  // Fig. 4: the paper's four phases stacked for each of the three groups.
  EXPECT_EQ(count(f.at("fig4_runtime.svg"), "<rect x="), 12);
}

TEST(Figures, TheAblationDrawsGainsAndRaySets) {
  const std::string csv =
      "gain,rays,p_gt,view,entropy_mean,entropy_std,coverage_mean,coverage_std\n"
      "osamcep,ours,1,1,5,1,0.1,0.01\nosamcep,ours,1,2,4,1,0.2,0.01\n"
      "rs,ours,1,1,5,1,0.1,0.01\nosamcep,sparse,1,1,6,1,0.05,0.01\n";
  const Figures f = ablation_figures(csv);
  ASSERT_EQ(f.size(), 2u);
  EXPECT_NE(f.at("gains.svg").find("Information gain metrics (rays: ours)"), std::string::npos);
  EXPECT_NE(f.at("gains.svg").find(">rs (P_gt 1)<"), std::string::npos);
  EXPECT_EQ(f.at("gains.svg").find("sparse"), std::string::npos);
  EXPECT_NE(f.at("rays.svg").find(">sparse (P_gt 1)<"), std::string::npos);
  EXPECT_TRUE(ablation_figures("gain,rays,p_gt,view\n").empty());
}

}  // namespace
}  // namespace canopy::jobs
