// The view-planner registry (nbv/view_planner.h): the built-in planners' table, one room each,
// and a planner from outside the library registered by name.

#include <gtest/gtest.h>

#include "canopy/common/error.h"
#include "canopy/nbv/planners/planners.h"
#include "canopy/nbv/view_planner.h"

// A planner from outside the library joins the registry by name: settings may name it, the
// factory gets its settings (context included), and names are unique and well formed.
namespace {
struct ContextProbe : canopy::nbv::PlannerContext {
  int value = 42;
};
class FixedPlanner : public canopy::nbv::ViewPlanner {
 public:
  explicit FixedPlanner(const canopy::nbv::ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), seen_(dynamic_cast<const ContextProbe*>(s.context.get())) {}
  std::string name() const override { return "test-fixed"; }
  canopy::nbv::ViewBatch next(const canopy::nbv::ViewRequest&) override {
    canopy::nbv::ViewBatch b;
    b.finished = true;
    b.reason = seen_ ? "context " + std::to_string(seen_->value) : "no context";
    return b;
  }

 private:
  const ContextProbe* seen_;
};
}  // namespace

TEST(ViewPlanner, RegisteredPlannersAreMadeByName) {
  using namespace canopy::nbv;
  register_view_planner({"test-fixed", "a planner that plans nothing",
                         [](const ViewPlannerSettings& s) { return std::unique_ptr<ViewPlanner>(new FixedPlanner(s)); }});
  const std::vector<std::string> names = view_planner_names();
  ASSERT_GE(names.size(), 4u);
  EXPECT_EQ(names[0], "ours");
  EXPECT_EQ(names.back(), "test-fixed");
  ViewPlannerSettings s;
  s.method.name = "test-fixed";
  s.context = std::make_shared<ContextProbe>();
  const auto p = make_view_planner(s);
  EXPECT_EQ(p->name(), "test-fixed");
  EXPECT_EQ(p->next(ViewRequest{}).reason, "context 42");
  EXPECT_THROW(register_view_planner({"test-fixed", "again", [](const ViewPlannerSettings& x) {
                                        return std::unique_ptr<ViewPlanner>(new FixedPlanner(x));
                                      }}),
               canopy::InputError);
  EXPECT_THROW(register_view_planner({"Bad Name", "", [](const ViewPlannerSettings& x) {
                                        return std::unique_ptr<ViewPlanner>(new FixedPlanner(x));
                                      }}),
               canopy::InputError);
  s.method.name = "no-such";
  EXPECT_THROW(make_view_planner(s), canopy::InputError);
}



// The failed-view rule (joins_failed_views): a view that failed for a cause of its own joins a
// planner's failed_views(), once; a start in collision or an unstable simulation says nothing
// about the view, and a success is no failure.
TEST(ViewPlanner, FailedViewRule) {
  using namespace canopy::nbv;
  ViewPlannerSettings s;
  FixedPlanner planner(s);
  const std::vector<std::pair<std::string, bool>> causes = {
      {"no_ik", true},           {"goal_in_collision", true}, {"plan_timeout", true}, {"invalid_input", true},
      {"not_reached", true},     {"start_in_collision", false}, {"unstable", false}};
  double x = 0.0;
  std::size_t joined = 0;
  for (const auto& [cause, joins] : causes) {
    ViewOutcome o;
    o.view.T_world_camera.translation() = canopy::Vec3(x += 1.0, 0.0, 0.0);  // a view of its own
    o.failure = cause;
    EXPECT_EQ(joins_failed_views(o), joins) << cause;
    planner.outcome(o);
    joined += joins;
    EXPECT_EQ(planner.failed_views().size(), joined) << cause;
    EXPECT_EQ(planner.failed_views().contains(o.view.T_world_camera), joins) << cause;
  }
  ViewOutcome again;  // the same view failing again is not added twice
  again.view.T_world_camera.translation() = canopy::Vec3(1.0, 0.0, 0.0);
  again.failure = "no_ik";
  planner.outcome(again);
  EXPECT_EQ(planner.failed_views().size(), joined);
  ViewOutcome ok;
  ok.success = true;
  EXPECT_FALSE(joins_failed_views(ok));
}
