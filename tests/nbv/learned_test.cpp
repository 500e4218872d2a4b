// The planner on the learned view scorer (nbv/planners/learned/) on the shape planner's scene:
// one fruit mapped from the front only, a leaf beside its back on +y. With a model trained to
// rank by the predicted unseen surface a view sees (shape_seen), it picks the view of the
// unseen back, as the shape planner does; a model file it cannot use is refused when the
// planner is made, naming the file.

#include <gtest/gtest.h>

#include <algorithm>

#include "canopy/common/error.h"
#include "canopy/nbv/planners/learned/learned.h"
#include "canopy/nbv/view_features.h"
#include "ranker_model.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

std::size_t feature_index(const std::string& name) {
  const auto& n = view_feature_names();
  return std::size_t(std::find(n.begin(), n.end(), name) - n.begin());
}

ViewPlannerSettings learned_settings(const std::string& model) {
  ViewPlannerSettings s;
  s.method.name = "learned";
  bool registered = false;
  for (const PlannerSection& p : s.params.planners) registered = registered || p.params.get<LearnedParams>();
  if (!registered) {  // its section, as the registry line adds it
    PlannerSection section = learned::entry().params;
    section.key = "learned";
    s.params.planners.push_back(section);
  }
  s.params.planner<LearnedParams>().model = model;
  return s;
}

TEST(Learned, WithAModelRankingByPredictedSurfaceItLooksAtTheUnseenBack) {
  const std::string model =
      nbv_test::train_model("by_shape_seen.json", feature_index("shape_seen"), {}, 300.f);
  const mapping::SemanticOcTree map = nbv_test::front_map(true);
  VoxelIndex index(map);
  const auto planner = learned::make_planner(learned_settings(model));
  EXPECT_EQ(planner->name(), "learned");
  ViewRequest req;
  req.map = &map;
  req.index = &index;
  req.region = Eigen::AlignedBox3d(Vec3(0.2, -0.4, 0.6), Vec3(0.8, 0.4, 1.4));
  std::size_t scored = 0;
  req.on_scored = [&](const ScoredView&) { ++scored; };
  const ViewBatch batch = planner->next(req);
  ASSERT_FALSE(batch.views.empty()) << batch.reason;
  EXPECT_EQ(batch.order, BatchOrder::kUtility);
  EXPECT_LE(batch.views.size(), 5u);
  EXPECT_GE(scored, batch.views.size());
  for (std::size_t i = 1; i < batch.views.size(); ++i) EXPECT_GE(batch.views[i - 1].gain, batch.views[i].gain);
  // The best view looks at the back (+x side of the fruit), not at the seen front.
  const Vec3 best = batch.views.front().T_world_camera.translation() - nbv_test::kShapeFruit;
  EXPECT_GT(best.x(), 0.0) << best.transpose();
  EXPECT_EQ(batch.views.front().source, "learned");
}

TEST(Learned, AModelFileItCannotUseIsRefusedNamingIt) {
  try {
    learned::make_planner(learned_settings("/nonexistent/view_ranker.json"));
    FAIL() << "no refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'/nonexistent/view_ranker.json': no such file"), std::string::npos) << e.what();
  }
}

}  // namespace
