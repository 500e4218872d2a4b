// The oracle's room (mission/oracle/; it reads the ground truth): the truth scorer with the
// simulator's render (make_truth_scorer) on a hand-built scene (a fruit behind a leaf), its
// coarse render against the full one and an analytic count, branch and bound against scoring
// every view, the oracle planners in a mission, the candidate audit and candidates.csv read by
// its header. The scorer alone, on an analytic render: tests/evaluation/truth_score_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/mission/mission.h"
#include "canopy/mission/oracle/candidate_audit.h"
#include "canopy/mission/oracle/oracle_planners.h"
#include "canopy/records/candidates_csv.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/planners/learned/learned_params.h"
#include "canopy/world/world_spec.h"

namespace canopy::mission {

// The records the mission fills in and the settings it reads, by their short names.
using namespace canopy::records;
using namespace canopy::settings;
namespace {

using evaluation::TruthScore;
using evaluation::TruthViewScorer;

// The mission's truth scorer of `sim` at the camera divided by `downsample`.
std::unique_ptr<TruthViewScorer> scorer_of(sim::Simulator& sim, const CameraIntrinsics& K, int downsample) {
  OracleParams p;
  p.render_downsample = downsample;
  p.depth_tolerance_m = 0.005;
  return make_truth_scorer(sim, K, p);
}

const Vec3 kFruit(0.0, 0.5, 1.0);
constexpr double kRadius = 0.04;

// A sphere "fruit" and a thin "leaf" between it and a camera on the -y side.
sim::SceneDescription fruit_behind_leaf() {
  sim::SceneDescription scene;
  scene.mjcf =
      "<mujoco><statistic extent=\"2\" center=\"0 0 0\"/><visual><global offwidth=\"400\" offheight=\"400\"/>"
      "<quality offsamples=\"0\" numslices=\"200\" numstacks=\"200\"/><map znear=\"0.01\" zfar=\"10\"/></visual>"
      "<worldbody><geom name=\"fruit\" type=\"sphere\" size=\"0.04\" pos=\"0 0.5 1.0\"/>"
      "<geom name=\"leaf\" type=\"box\" size=\"0.06 0.001 0.06\" pos=\"0 0.3 1.0\"/></worldbody></mujoco>";
  scene.labels["fruit"] = sim::GeomLabel{2, 7, false};
  scene.labels["leaf"] = sim::GeomLabel{1, kNoInstance, false};
  return scene;
}

// Points evenly on the fruit's surface (a Fibonacci sphere).
std::vector<evaluation::UncoveredPoint> fruit_points(int n) {
  std::vector<evaluation::UncoveredPoint> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    out.push_back({kFruit + kRadius * Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z), 7});
  }
  return out;
}

// Points a lone sphere shows a camera at `eye`: those facing it at an incidence cosine above
// `min_cos` (0: every point of the visible cap).
std::size_t facing(const std::vector<evaluation::UncoveredPoint>& pts, const Vec3& eye, double min_cos) {
  std::size_t n = 0;
  for (const auto& p : pts) n += (p.position - kFruit).normalized().dot((eye - p.position).normalized()) > min_cos;
  return n;
}

TEST(Oracle, FruitBehindALeafIsNotSeenAndTheUnoccludedViewWins) {
  sim::Simulator sim(fruit_behind_leaf());
  const CameraIntrinsics K;
  const auto owned = scorer_of(sim, K, 4);
  TruthViewScorer& scorer = *owned;
  const std::vector<evaluation::UncoveredPoint> pts = fruit_points(2000);
  scorer.set_points(pts);
  const Vec3 eye_leaf(0.0, 0.1, 1.0), eye_side(0.4, 0.5, 1.0), eye_top(0.0, 0.5, 1.4);
  std::vector<Pose> views = {look_at(eye_leaf, kFruit), look_at(eye_side, kFruit), look_at(eye_top, kFruit),
                             look_at(eye_leaf, eye_leaf - Vec3(0, 1, 0))};  // the last looks away
  // Through the leaf: the whole fruit lies in the frustum and none of it is seen.
  EXPECT_GT(scorer.in_frustum(views[0]), 1500u);
  EXPECT_EQ(scorer.visible(views[0]), 0u);
  EXPECT_EQ(scorer.in_frustum(views[3]), 0u);
  EXPECT_EQ(scorer.visible(views[3]), 0u);
  // From the side: every point the camera faces at less than 70 deg incidence, and none it
  // does not face (grazing points fail the depth test where a pixel spans a steep slope).
  const std::size_t side = scorer.visible(views[1]);
  EXPECT_GE(side, facing(pts, eye_side, std::cos(70.0 * M_PI / 180.0)));
  EXPECT_LE(side, facing(pts, eye_side, 0.0));
  const std::vector<TruthScore> best = evaluation::best_truth_views(scorer, &views, 1);
  ASSERT_EQ(best.size(), 1u);
  EXPECT_TRUE(best[0].view == 1 || best[0].view == 2);  // an unoccluded view, never the one behind the leaf
  EXPECT_GE(best[0].score, side);
}

TEST(Oracle, CoarseRenderAgreesWithTheFullOne) {
  sim::Simulator sim(fruit_behind_leaf());
  const CameraIntrinsics K;
  const auto full_scorer = scorer_of(sim, K, 1), coarse_scorer = scorer_of(sim, K, 4);
  TruthViewScorer &full = *full_scorer, &coarse = *coarse_scorer;
  const std::vector<evaluation::UncoveredPoint> pts = fruit_points(2000);
  full.set_points(pts);
  coarse.set_points(pts);
  ViewSphere sphere;
  sphere.radius_m = 0.3;
  sphere.polar_count = 4;
  sphere.azimuth_count = 6;
  int compared = 0;
  for (const SphereView& v : sphere_views(kFruit, sphere)) {
    const double a = double(full.visible(v.T_world_camera)), b = double(coarse.visible(v.T_world_camera));
    // Partly occluded views differ by the leaf's silhouette at the coarse pixel size.
    EXPECT_NEAR(b, a, 0.04 * double(pts.size())) << "polar " << v.polar_deg << " azimuth " << v.azimuth_deg;
    compared += a > 0;
  }
  EXPECT_GT(compared, 15);
  EXPECT_EQ(full.render_intrinsics().width_px, 4 * coarse.render_intrinsics().width_px);
}

TEST(Oracle, BranchAndBoundEqualsScoringEveryView) {
  sim::Simulator sim(fruit_behind_leaf());
  const auto owned = scorer_of(sim, CameraIntrinsics{}, 4);
  TruthViewScorer& scorer = *owned;
  scorer.set_points(fruit_points(1500));
  ViewSphere sphere;
  sphere.radius_m = 0.35;
  sphere.polar_count = 5;
  sphere.azimuth_count = 8;
  std::vector<Pose> views;
  for (const SphereView& v : sphere_views(kFruit, sphere)) views.push_back(v.T_world_camera);
  // Views looking away from the fruit: their frustum holds no point, they are never rendered.
  for (int i = 0; i < 10; ++i) {
    const Vec3 eye = kFruit + Vec3(0.3 * std::cos(i), 0.3 * std::sin(i), 0.05 * i);
    views.push_back(look_at(eye, 2.0 * eye - kFruit));
  }
  std::vector<std::pair<std::size_t, std::size_t>> every;  // (score, view)
  for (std::size_t i = 0; i < views.size(); ++i) every.push_back({scorer.visible(views[i]), i});
  std::stable_sort(every.begin(), every.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const std::size_t renders_before = scorer.renders();
  std::vector<Pose> copy = views;
  const std::vector<TruthScore> best = evaluation::best_truth_views(scorer, &copy, 5);
  ASSERT_EQ(best.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(best[k].view, every[k].second) << k;
    EXPECT_EQ(best[k].score, every[k].first) << k;
  }
  EXPECT_LE(scorer.renders() - renders_before, views.size() - 10);  // the bound spared renders
  // A refused view is skipped.
  const std::vector<TruthScore> refused =
      evaluation::best_truth_views(scorer, &copy, 1, [&](std::size_t i, Pose*) { return i != every[0].second; });
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_NE(refused[0].view, every[0].second);
}

struct OracleWorld {
  world::World world;
  Settings settings;
  OracleWorld() : world(world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")))),
                 settings(Settings::defaults(default_robot_config())) {
    settings.mapping.extractor.source = perception::LabelSource::kTruth;
    settings.mapping.extractor.p_gt = 1.0;
    settings.mission.stops.count = 1;
    settings.mission.loop.views_per_stop = 3;
  }
};

// Runs the mission of `s` on `w`'s world and checks what every oracle does: each successful NBV
// view is `source`'s and one the truth says sees uncovered points, at least one succeeds (a view
// that leaves the wrist touching the chassis stops the arm: start_in_collision, a controller limit
// the experiments report), and the coverage grows past the initial scan's. `each` sees every NBV
// view of `source`, successful or not.
void expect_an_oracle_mission(const OracleWorld& w, const Settings& s, const std::string& source,
                              const std::function<void(const ViewRecord&)>& each = {}) {
  Mission m(w.world, s, 1);
  const MissionResult r = m.run();
  int nbv_ok = 0;
  double before = 0.0;
  for (const ViewRecord& v : r.views) {
    if (v.phase == ViewPhase::kInitial && v.success) before = v.coverage;
    if (v.phase != ViewPhase::kNbv) continue;
    if (each && v.source == source) each(v);
    if (!v.success) continue;
    ++nbv_ok;
    EXPECT_EQ(v.source, source);
    EXPECT_GT(v.gain, 0.0);
  }
  EXPECT_GE(nbv_ok, 1) << source;
  EXPECT_GT(r.final_metrics.coverage, before) << source;
}

TEST(Oracle, OraclePlannersRunInAMissionAndSayTheyReadTheTruth) {
  const OracleWorld w;
  for (const char* name : {"oracle", "oracle_any"}) {
    const nbv::ViewPlannerEntry* e = nbv::find_view_planner(name);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_TRUE(e->reads_ground_truth);
    EXPECT_NE(e->description.find("GROUND TRUTH"), std::string::npos);
    Settings s = w.settings;
    s.method.name = name;
    expect_an_oracle_mission(w, s, name);
  }
  // Outside a mission there is no truth to read.
  nbv::ViewPlannerSettings ps;
  ps.method.name = "oracle";
  EXPECT_THROW(nbv::make_view_planner(ps), InputError);
}

// mission.oracle.candidates "learned": the oracle scores learned's candidates (spheres of
// nbv.learned.radii_m around the fitted fruit centres) instead of ours' (spheres of
// nbv.candidates.sphere.radius_m, 0.4 m). The reach test moves a view along its line in steps of
// 1 cm, so a view's distance to its target keeps its sphere's radius modulo 1 cm: 0.335 m (5 mm)
// for learned's, 0.4 m (0 mm) for ours'.
TEST(Oracle, OracleOnLearnedsCandidatesScoresThemByTheTruth) {
  const OracleWorld w;
  for (const char* set : {"ours", "learned"}) {
    Settings s = w.settings;
    s.method.name = "oracle";
    s.mission.oracle.candidates = set;
    s.nbv.planner<nbv::LearnedParams>().radii_m = {0.335};
    ASSERT_DOUBLE_EQ(s.motion.workspace.shift_step_m, 0.01);
    ASSERT_DOUBLE_EQ(s.nbv.candidates.sphere.radius_m, 0.4);
    expect_an_oracle_mission(w, s, "oracle", [&](const ViewRecord& v) {
      const double d_mm = 1000.0 * (v.T_goal.translation() - v.target).norm();
      const double residue = std::fmod(d_mm + 0.5, 10.0) - 0.5;  // in [-0.5, 9.5)
      EXPECT_NEAR(residue, std::string(set) == "learned" ? 5.0 : 0.0, 1e-3) << set << " view " << v.attempt;
    });
  }
  Settings bad = w.settings;
  EXPECT_THROW(bad.set("mission.oracle.candidates", "mine", "--set"), InputError);
}

TEST(Oracle, CandidateAuditScoresEveryCandidateByEveryGainAndTheTruth) {
  OracleWorld w;
  w.settings.mission.record.candidates = true;
  w.settings.mission.loop.views_per_stop = 2;
  Mission m(w.world, w.settings, 1);
  const MissionResult r = m.run();
  ASSERT_FALSE(r.candidates.empty());
  std::set<int> rounds, chosen_rounds;
  for (const CandidateRecord& c : r.candidates) {
    ASSERT_EQ(c.scores.size(), audit_score_names().size());
    EXPECT_LE(c.truth, c.frustum);
    EXPECT_GE(c.scores[2], 0.0);  // ae
    rounds.insert(c.round);
    if (c.chosen) {
      EXPECT_TRUE(chosen_rounds.insert(c.round).second) << "two chosen views in round " << c.round;
    }
    // The planner's gain is osamcep with the default proximity test.
    EXPECT_NEAR(c.planner_gain, c.scores[1], 1e-9 * std::max(1.0, std::abs(c.planner_gain)));
  }
  EXPECT_GE(chosen_rounds.size(), 1u);
  EXPECT_LE(chosen_rounds.size(), rounds.size());
  const std::string csv = candidates_csv(r.candidates);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), long(r.candidates.size()) + 1);
  // Read back: per round, each score against the truth, as RankAgreement computes it.
  const std::string file = testing::TempDir() + "/oracle_test_candidates.csv";
  write_file_atomic(file, csv);
  const std::vector<GainTruthRow> rows = gain_truth({file});
  ASSERT_EQ(rows.size(), audit_score_names().size() + 1);
  evaluation::RankAgreement expected;
  for (const int round : rounds) {
    std::vector<double> gain, truth;
    for (const CandidateRecord& c : r.candidates)
      if (c.round == round) {
        gain.push_back(c.planner_gain);
        truth.push_back(double(c.truth));
      }
    if (truth.size() >= 2) expected.add_round(gain, truth);
  }
  EXPECT_EQ(rows[0].score, "planner");
  EXPECT_EQ(rows[0].agreement.rounds, expected.rounds);
  EXPECT_NEAR(rows[0].agreement.mean_rank(), expected.mean_rank(), 1e-9);
  EXPECT_NEAR(rows[0].agreement.mean_spearman(), expected.mean_spearman(), 1e-6);
  EXPECT_THROW(gain_truth({file + ".missing"}), InputError);
}

// candidates.csv is read by its header's names: columns in another order give the same table,
// a missing score column is named; the scores are the gain registry's, osamcep once per
// proximity test.
TEST(Oracle, CandidatesCsvIsReadByItsHeader) {
  std::vector<std::string> expected;
  for (const nbv::GainEntry& g : nbv::gain_registry()) {
    if (!g.uses_proximity) expected.push_back(g.name);
    else
      for (const auto& p : nbv::kProximityNames) expected.push_back(g.name + "_" + p.name);
  }
  EXPECT_EQ(audit_score_names(), expected);
  ASSERT_EQ(expected.size(), nbv::gain_registry().size() + 1);
  // Two rounds of three candidates; score k of candidate i is (i * (k + 1)) % 5.
  std::vector<CandidateRecord> records;
  for (int round = 0; round < 2; ++round)
    for (int i = 0; i < 3; ++i) {
      CandidateRecord r;
      r.round = round;
      r.planner_gain = double(3 - i);
      r.truth = std::size_t(i + round);
      r.frustum = r.truth + 1;
      for (std::size_t k = 0; k < expected.size(); ++k) r.scores.push_back(double((i * int(k + 1)) % 5));
      records.push_back(r);
    }
  const std::string csv = candidates_csv(records);
  const std::string file = testing::TempDir() + "/oracle_test_header.csv";
  write_file_atomic(file, csv);
  const std::vector<GainTruthRow> rows = gain_truth({file});
  // The same file with its columns reversed.
  std::string reversed;
  std::istringstream in(csv);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::istringstream ls(line);
    for (std::string item; std::getline(ls, item, ',');) f.push_back(item);
    std::reverse(f.begin(), f.end());
    for (std::size_t k = 0; k < f.size(); ++k) reversed += (k ? "," : "") + f[k];
    reversed += "\n";
  }
  write_file_atomic(file + ".rev", reversed);
  const std::vector<GainTruthRow> again = gain_truth({file + ".rev"});
  ASSERT_EQ(rows.size(), expected.size() + 1);
  ASSERT_EQ(again.size(), rows.size());
  EXPECT_EQ(rows[0].agreement.rounds, 2u);
  EXPECT_NEAR(rows[0].agreement.mean_spearman(), -1.0, 1e-12);  // the planner ranks the truth backwards
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(again[k].score, rows[k].score);
    EXPECT_EQ(again[k].agreement.rounds, rows[k].agreement.rounds);
    EXPECT_EQ(again[k].agreement.mean_spearman(), rows[k].agreement.mean_spearman()) << rows[k].score;
    EXPECT_EQ(again[k].agreement.mean_rank(), rows[k].agreement.mean_rank()) << rows[k].score;
  }
  // A file without the column of a score is refused, naming the column.
  write_file_atomic(file + ".short", "stop,round,planner_gain,truth\n0,0,1,2\n");
  try {
    gain_truth({file + ".short"});
    ADD_FAILURE() << "a candidates.csv without its score columns was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no column 'osamcep_per_voxel'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace canopy::mission
