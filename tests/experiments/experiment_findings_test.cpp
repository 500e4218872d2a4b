// The findings (experiment_findings.cpp through make_experiment_report): structured blocks that
// findings.md renders, and the analyses that were tools/goal_check.py and tools/sc_per_view.py,
// checked on hand-made trials whose figures are computed here by hand.

#include <gtest/gtest.h>

#include <string>

#include "canopy/experiments/experiment_report.h"

namespace canopy::experiments {
namespace {

TrialResult trial(const std::string& method, std::uint64_t world, std::vector<double> sc, std::vector<std::string> phases) {
  TrialResult t;
  t.spec.method.label = method;
  t.spec.method.choice.name = method;
  t.spec.p_gt = 1.0;
  t.spec.world_seed = world;
  t.spec.id = trial_id(method, 1.0, 1, world);
  t.status = "ok";
  t.folder = "/nonexistent/canopy-findings-test/" + t.spec.id;
  t.coverage = std::move(sc);
  t.entropy.assign(t.coverage.size(), 1.0);
  t.phases = std::move(phases);
  t.views_ok = static_cast<int>(t.coverage.size());
  t.views_attempted = t.views_ok;
  t.stops = 1;
  return t;
}

// Trials of frontier, shape and the oracle on worlds 1001 and 1002; frontier and shape also on
// 1003, where the oracle has none: the matched worlds are 1001 and 1002.
MergedTrials hand_made() {
  MergedTrials m;
  m.names = {"hand"};
  const std::vector<std::string> two = {"initial", "nbv"};
  m.trials = {trial("frontier", 1001, {0.1, 0.3}, two), trial("frontier", 1002, {0.2, 0.4}, two),
              trial("frontier", 1003, {0.1, 0.2}, two), trial("shape", 1001, {0.2, 0.5}, two),
              trial("shape", 1002, {0.2, 0.6}, two),    trial("shape", 1003, {0.1, 0.1}, two),
              trial("oracle", 1001, {0.3, 0.8}, two),   trial("oracle", 1002, {0.3, 0.9}, two)};
  for (const TrialResult& t : m.trials) m.expected.push_back(t.spec);
  return m;
}

// The blocks after the heading whose text starts with `title`, up to the next heading.
nlohmann::json section(const nlohmann::json& blocks, const std::string& title) {
  nlohmann::json out = nlohmann::json::array();
  bool in = false;
  for (const nlohmann::json& b : blocks) {
    if (b.at("kind") == "heading") in = b.at("text").get<std::string>().rfind(title, 0) == 0;
    else if (in) out.push_back(b);
  }
  return out;
}

TEST(ExperimentFindings, MatchedWorldsCarrySCForwardAndHoldEachMethodAgainstTheBaselinesAndTheOracle) {
  const ExperimentReport r = make_experiment_report(hand_made());
  const nlohmann::json s = section(r.findings, "6.");
  ASSERT_EQ(s.size(), 4u) << s.dump(1);  // intro, P_gt caption, table, checks
  EXPECT_EQ(s[1].at("text"), "P_gt 1: 2 worlds every method completed (1001, 1002)");
  // Two views each: SC after 30, 60 and 90 carry the last figure forward. frontier: (0.3 + 0.4) / 2,
  // std 0.0707; shape 0.55 ± 0.0707; the oracle 0.85 ± 0.0707.
  const nlohmann::json rows = s[2].at("rows");
  ASSERT_EQ(rows.size(), 3u);
  const std::string f = "0.350 ± 0.071 (n=2)", sh = "0.550 ± 0.071 (n=2)", o = "0.850 ± 0.071 (n=2)";
  EXPECT_EQ(rows[0], nlohmann::json({"frontier", f, f, f, f, "2.0"}));
  EXPECT_EQ(rows[1], nlohmann::json({"shape", sh, sh, sh, sh, "2.0"}));
  EXPECT_EQ(rows[2], nlohmann::json({"oracle (reads the truth)", o, o, o, o, "2.0"}));
  // shape beats frontier everywhere, but not half the way to the oracle: 0.35 + (0.85 - 0.35) / 2 = 0.6.
  ASSERT_EQ(s[3].at("items").size(), 1u);
  EXPECT_EQ(s[3].at("items")[0],
            "shape against the better of frontier: after 30: 0.550 vs 0.350 ok; after 60: 0.550 vs 0.350 ok; after 90: "
            "0.550 vs 0.350 ok; after final: 0.550 vs 0.350 ok; half way to the oracle after 60: 0.550 vs 0.600 NOT met");
}

TEST(ExperimentFindings, CoverageAddedPerViewByPhase) {
  const ExperimentReport r = make_experiment_report(hand_made());
  const nlohmann::json s = section(r.findings, "7.");
  ASSERT_EQ(s.size(), 2u) << s.dump(1);
  const nlohmann::json rows = s[1].at("rows");
  ASSERT_EQ(rows.size(), 3u);
  // shape: the initial views added 0.2, 0.2, 0.1 (200, 200, 100 thousandths: 166.7 ± 57.7), the
  // later ones 0.3, 0.4, 0 (233.3 ± 208.2), over all three worlds.
  EXPECT_EQ(rows[1], nlohmann::json({"1", "shape", "167 ± 57.7 (n=3)", "233 ± 208 (n=3)"}));
  // Without phases (old views.csv) every view counts as a later one: 0.5, 0.6, 0.1 over two views
  // each (250, 300, 50: 200 ± 132.3).
  MergedTrials m = hand_made();
  for (TrialResult& t : m.trials) t.phases.clear();
  const nlohmann::json rows2 = section(make_experiment_report(m).findings, "7.")[1].at("rows");
  EXPECT_EQ(rows2[1], nlohmann::json({"1", "shape", "n/a", "200 ± 132 (n=3)"}));
}

TEST(ExperimentFindings, MarkdownRendersTheBlocks) {
  const nlohmann::json blocks = nlohmann::json::parse(R"([
    {"kind": "heading", "level": 1, "text": "Findings: x"},
    {"kind": "paragraph", "text": "Some text.", "strong": false},
    {"kind": "paragraph", "text": "Caption", "strong": true},
    {"kind": "table", "header": ["a", "b"], "rows": [["1", "2"], ["3", "4"]]},
    {"kind": "list", "items": ["one", "two"]}])");
  EXPECT_EQ(findings_markdown(blocks),
            "# Findings: x\n\nSome text.\n\n**Caption**\n\n| a | b |\n|---|---|\n| 1 | 2 |\n| 3 | 4 |\n\n- one\n- two\n");
  EXPECT_THROW(findings_markdown(nlohmann::json::parse(R"([{"kind": "poem"}])")), std::logic_error);
  const ExperimentReport r = make_experiment_report(hand_made());
  EXPECT_EQ(r.findings_md, findings_markdown(r.findings));
  EXPECT_EQ(r.findings_md.rfind("# Findings: hand\n\nTrials: 8 expected, 8 ok, 0 failed", 0), 0u) << r.findings_md;
}

}  // namespace
}  // namespace canopy::experiments
