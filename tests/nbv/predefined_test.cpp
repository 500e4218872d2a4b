// Dense predefined scanning (nbv/planners/predefined/): its one batch per stop of the scripted
// views not taken, and its replacement of a failed scripted view (replace_failed) against
// hand-made options: nearest first, no scripted view or earlier replacement repeated, views
// without IK skipped, at most max_attempts attempted and never past the stop's budget.

#include <gtest/gtest.h>

#include "canopy/nbv/planners/planners.h"
#include "canopy/nbv/planners/predefined/predefined.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

Pose at(double x) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(x, 0.0, 1.0);
  return T;
}

PlannedView view_at(double x) {
  PlannedView v;
  v.T_world_camera = at(x);
  v.source = "replacement";
  return v;
}

std::unique_ptr<ViewPlanner> predefined_planner() {
  ViewPlannerSettings s;
  s.method.name = "predefined";
  return make_view_planner(s);
}

}  // namespace

TEST(Predefined, OneBatchOfTheScriptedViewsNotTakenPerStop) {
  const auto p = predefined_planner();
  const PlannerTraits t = p->traits();
  EXPECT_TRUE(t.scripted && t.execute_whole_batch && t.replaces_failed);
  ViewRequest req;
  req.scripted = {at(0.0), at(0.1), at(0.2)};
  p->taken(at(0.1));
  const ViewBatch b = p->next(req);
  ASSERT_EQ(b.views.size(), 2u);
  EXPECT_TRUE(b.views[1].T_world_camera.isApprox(at(0.2)));
  EXPECT_EQ(b.views[0].source, "predefined");
  EXPECT_EQ(b.order, BatchOrder::kTour);
  EXPECT_TRUE(b.last_of_stop);
  EXPECT_TRUE(p->next(req).finished);  // served once per stop
  p->begin_stop();
  EXPECT_EQ(p->next(req).views.size(), 2u);
}

// With the goal test at planning (the default), scripted views that would fail before the arm
// moves are refused (handed on to be replaced, not in the batch); with it off they are sent.
TEST(Predefined, RefusesScriptedViewsWithoutAFreeGoalBeforeAnyMove) {
  ViewRequest req;
  req.scripted = {at(0.0), at(0.1), at(0.2), at(0.3)};
  int tested = 0;
  req.goal_free = [&](const PlannedView& v) {
    ++tested;
    const double x = v.T_world_camera.translation().x();
    return x != 0.1 && x != 0.3;
  };
  const auto p = predefined_planner();
  const ViewBatch b = p->next(req);
  EXPECT_EQ(tested, 4);
  ASSERT_EQ(b.views.size(), 2u);
  EXPECT_TRUE(b.views[0].T_world_camera.isApprox(at(0.0)));
  EXPECT_TRUE(b.views[1].T_world_camera.isApprox(at(0.2)));
  ASSERT_EQ(b.refused.size(), 2u);
  EXPECT_TRUE(b.refused[0].T_world_camera.isApprox(at(0.1)));
  EXPECT_TRUE(b.refused[1].T_world_camera.isApprox(at(0.3)));
  EXPECT_EQ(b.candidates, 4u);
  EXPECT_EQ(b.filtered, 2u);
  EXPECT_FALSE(b.finished);
  // Every view refused: still a batch to replace, not a finished stop.
  req.goal_free = [](const PlannedView&) { return false; };
  p->begin_stop();
  const ViewBatch none = p->next(req);
  EXPECT_TRUE(none.views.empty());
  EXPECT_EQ(none.refused.size(), 4u);
  EXPECT_FALSE(none.finished);
  // The authors' protocol: every scripted view is sent.
  ViewPlannerSettings s;
  s.method.name = "predefined";
  s.params.planner<PredefinedParams>().goal_test_at_planning = false;
  const auto off = make_view_planner(s);
  const ViewBatch all = off->next(req);
  EXPECT_EQ(all.views.size(), 4u);
  EXPECT_TRUE(all.refused.empty());
}

TEST(Predefined, ReplacesAFailedViewByTheNearestReachableOneNotUsedBefore) {
  const auto p = predefined_planner();
  p->begin_stop();
  FailedScriptedView req;
  req.failed = view_at(0.0);
  req.scripted = {at(0.0), at(0.1)};
  req.options = {view_at(0.1), view_at(0.2), view_at(0.3), view_at(0.4), view_at(0.5), view_at(0.6)};
  req.max_attempts = 2;
  req.reachable = [](const PlannedView& v) { return v.T_world_camera.translation().x() != 0.2; };  // no IK at 0.2
  std::vector<double> attempted;
  bool succeed_at_04 = true;
  req.attempt = [&](const PlannedView& v) {
    attempted.push_back(v.T_world_camera.translation().x());
    return succeed_at_04 && v.T_world_camera.translation().x() == 0.4;
  };
  // 0.1 is a scripted view, 0.2 has no IK: 0.3 fails, 0.4 succeeds.
  EXPECT_TRUE(p->replace_failed(req));
  EXPECT_EQ(attempted, (std::vector<double>{0.3, 0.4}));
  // The next failed view of the stop: 0.3 and 0.4 were tried already; two attempts at most.
  attempted.clear();
  succeed_at_04 = false;
  EXPECT_FALSE(p->replace_failed(req));
  EXPECT_EQ(attempted, (std::vector<double>{0.5, 0.6}));
  // A new stop forgets the replacements; the stop's budget (which the controller's attempt
  // spends) ends the tries.
  p->begin_stop();
  attempted.clear();
  int left = 0;
  req.attempts_left = &left;
  EXPECT_FALSE(p->replace_failed(req));
  EXPECT_TRUE(attempted.empty());
  left = 1;
  req.attempt = [&](const PlannedView& v) {
    --left;
    attempted.push_back(v.T_world_camera.translation().x());
    return false;
  };
  EXPECT_FALSE(p->replace_failed(req));
  EXPECT_EQ(attempted, (std::vector<double>{0.3}));
}

// Other planners replace nothing: every built-in one but predefined (the oracles are built by
// a mission only).
TEST(Predefined, OnlyPredefinedReplaces) {
  for (const ViewPlannerEntry& e : builtin_view_planners()) {
    if (e.name == "predefined" || e.reads_ground_truth) continue;
    const std::string& name = e.name;
    ViewPlannerSettings s;
    s.method.name = name;
    const auto p = make_view_planner(s);
    EXPECT_FALSE(p->traits().replaces_failed) << name;
    FailedScriptedView req;
    req.options = {view_at(0.3)};
    req.max_attempts = 4;
    req.attempt = [](const PlannedView&) {
      ADD_FAILURE() << "attempted";
      return true;
    };
    EXPECT_FALSE(p->replace_failed(req)) << name;
  }
}
