// The ablation's protocols (issue 10 point 6): the paper's fixed grid of 10 initial poses and
// its rounds (every unfinished cluster's best view taken before re-clustering), against the
// one-view-per-step protocol.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"
#include "canopy/robot/robot_config.h"
#include "canopy/experiments/ablation.h"
#include "canopy/experiments/ablation_runner.h"
#include "canopy/settings/settings.h"
#include "canopy/sim/simulator.h"

namespace canopy::experiments {
using namespace canopy::settings;
namespace {

// The paper's matrix: every gain with our rays, OSAMCEP with the other ray sets; OSAMCEP once
// per proximity test; everything once per value of a sweep; all at every P_gt.
TEST(Ablation, MatrixCrossesGainsRaysProximitiesSweepsAndPgt) {
  const std::vector<AblationConfig> c = ablation_matrix({"osamcep", "ae"}, {"ours", "dense"}, {1.0, 0.7},
                                                        {"per_voxel", "per_segment_end"},
                                                        {{"mapping.map.ray_range_m", {"0.8", "3"}}});
  // Per P_gt: osamcep-ours 2 x 2, ae-ours 2, osamcep-dense 2 x 2.
  ASSERT_EQ(c.size(), 20u);
  std::set<std::string> ids;
  for (const auto& x : c) ids.insert(x.id());
  EXPECT_EQ(ids.size(), c.size());
  EXPECT_EQ(c[0].id(), "osamcep-per_voxel-ray_range_m=0.8_ours_pgt1.00");
  EXPECT_EQ(c[4].id(), "ae-ray_range_m=0.8_ours_pgt1.00");
  EXPECT_EQ(c[6].id(), "osamcep-per_voxel-ray_range_m=0.8_dense_pgt1.00");
  EXPECT_EQ(c[10].pgt, 0.7);
  // Without proximities or sweeps: the plain matrix and the plain labels of earlier runs.
  const std::vector<AblationConfig> plain = ablation_matrix({"osamcep", "rs"}, {"ours", "sparse"}, {1.0}, {});
  ASSERT_EQ(plain.size(), 3u);
  EXPECT_EQ(plain[0].id(), "osamcep_ours_pgt1.00");
  EXPECT_EQ(plain[2].id(), "osamcep_sparse_pgt1.00");
  // A configuration's settings: the method, P_gt, its settings and the protocol's threshold.
  AblationSettings set;
  set.cluster_min_logodds = 0.5;
  const Settings s = ablation_job_settings(Settings::defaults(default_robot_config()), c[11], set);
  EXPECT_EQ(s.method.name, "ours");
  EXPECT_EQ(s.method.gain, "osamcep");
  EXPECT_EQ(s.mapping.extractor.p_gt, 0.7);
  EXPECT_EQ(s.nbv.gain.proximity, nbv::Proximity::kPerVoxel);
  EXPECT_EQ(s.mapping.map.ray_range_m, 3.0);
  EXPECT_EQ(s.nbv.cluster.min_logodds, 0.5);
}

TEST(Ablation, GridPosesAreThePapersTen) {
  AblationSettings set;
  const Vec3 base(3.0, 0.75, 0.0), aim = base + Vec3(0, 0, 0.5);
  std::set<std::pair<long, long>> seen;
  for (int trial = 0; trial < 10; ++trial) {
    const Pose T = ablation_grid_pose(base, trial, set);
    const Vec3 eye = T.translation(), d = eye - aim;
    EXPECT_NEAR(d.norm(), 0.4, 1e-12) << trial;
    // The camera looks at the aim point (optical axis = +z of the camera frame).
    EXPECT_NEAR((T.linear().col(2) - (-d.normalized())).norm(), 0.0, 1e-9) << trial;
    const double polar = std::acos(d.z() / d.norm()) * 180.0 / M_PI;
    const double azimuth = std::atan2(d.y(), d.x()) * 180.0 / M_PI;
    EXPECT_NEAR(polar, trial < 5 ? 30.0 : 120.0, 1e-9) << trial;
    EXPECT_NEAR(azimuth, 22.5 * (trial % 5), 1e-9) << trial;
    seen.insert({std::lround(polar), std::lround(azimuth * 10)});
    // Trial i + 10 starts where trial i did.
    EXPECT_TRUE(ablation_grid_pose(base, trial + 10, set).isApprox(T)) << trial;
  }
  EXPECT_EQ(seen.size(), 10u);
  EXPECT_EQ(ablation_protocol_from_string("one_view", "t"), AblationProtocol::kOneView);
  EXPECT_THROW(ablation_protocol_from_string("rounds", "t"), InputError);
}

class AblationJob : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/ablation.yaml"));
    spec.rows.plants_per_row = 1;
    world_ = new world::World(world::generate_world(spec));
    sim_ = new sim::Simulator(*world_, default_robot_config());
    renderer_ = new sim::Renderer(*sim_, spec.camera);
  }
  static void TearDownTestSuite() {
    delete renderer_;
    delete sim_;
    delete world_;
  }
  static nlohmann::json run(AblationProtocol protocol, int views) {
    settings::Settings s = settings::Settings::defaults(default_robot_config());
    s.mapping.extractor.source = perception::LabelSource::kTruth;
    AblationSettings set;
    set.protocol = protocol;
    set.views = views;
    set.cluster_min_logodds = protocol == AblationProtocol::kPaper ? 0.5 : -1.0;
    return run_ablation_job({"osamcep", "ours", 1.0, {{"nbv.gain.proximity", "per_segment_end"}}}, 3, 0, set, s, *world_, *renderer_);
  }
  static world::World* world_;
  static sim::Simulator* sim_;
  static sim::Renderer* renderer_;
};
world::World* AblationJob::world_ = nullptr;
sim::Simulator* AblationJob::sim_ = nullptr;
sim::Renderer* AblationJob::renderer_ = nullptr;

// Paper protocol: one initial view at grid pose 3; then rounds. A round's views come from one
// planning step (only its first view carries the planning figures) and are at most one per
// cluster; the next round plans again on the map all of them made.
TEST_F(AblationJob, PaperProtocolTakesWholeRounds) {
  const nlohmann::json j = run(AblationProtocol::kPaper, 10);
  EXPECT_EQ(j["protocol"], "paper");
  EXPECT_EQ(j["gain"], "osamcep-per_segment_end");
  const auto& steps = j["steps"];
  ASSERT_EQ(steps.size(), 10u);
  EXPECT_EQ(steps[0]["source"], "initial");
  const Pose T0 = pose_from_json(steps[0]["pose"]);
  EXPECT_TRUE(T0.isApprox(ablation_grid_pose(world_->plants[0].base_position, 3, AblationSettings{}), 1e-9));
  std::map<int, int> views_in_round, clusters_of_round;
  for (std::size_t i = 1; i < steps.size(); ++i) {
    const int round = steps[i]["round"].get<int>();
    if (steps[i].contains("clusters")) {
      EXPECT_EQ(clusters_of_round.count(round), 0u) << "round " << round << " planned twice";
      clusters_of_round[round] = steps[i]["clusters"].get<int>();
    } else {
      EXPECT_EQ(steps[i - 1]["round"].get<int>(), round) << "a round's later views follow its first";
    }
    if (steps[i]["source"] == "nbv") ++views_in_round[round];
  }
  bool some_round_has_several = false;
  for (const auto& [round, n] : views_in_round) {
    EXPECT_LE(n, clusters_of_round[round]) << "round " << round;
    some_round_has_several |= n > 1;
  }
  EXPECT_TRUE(some_round_has_several) << "no round executed more than one view";
  // Coverage never drops with true labels, and the planned views are all different (an empty
  // round looks again from where the camera is).
  std::set<std::string> poses;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(steps[i]["coverage_paper"].get<double>(), steps[i - 1]["coverage_paper"].get<double>() - 1e-12);
    }
    if (steps[i]["source"] == "nbv") {
      EXPECT_TRUE(poses.insert(steps[i]["pose"].dump()).second) << "view " << i + 1;
    }
  }
}

// one_view protocol: two random initial views, then every view has its own planning step.
TEST_F(AblationJob, OneViewProtocolReplansEveryView) {
  const nlohmann::json j = run(AblationProtocol::kOneView, 6);
  const auto& steps = j["steps"];
  ASSERT_EQ(steps.size(), 6u);
  EXPECT_EQ(steps[0]["source"], "initial");
  EXPECT_EQ(steps[1]["source"], "initial");
  for (std::size_t i = 2; i < steps.size(); ++i) EXPECT_TRUE(steps[i].contains("clusters")) << i;
}

}  // namespace
}  // namespace canopy::experiments
