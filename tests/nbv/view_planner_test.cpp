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


// The registry starts with the table of built-in planners, each made by its own entry.
TEST(ViewPlanner, BuiltInPlannersComeFromTheirRoomsInTheTablesOrder) {
  using namespace canopy::nbv;
  const std::vector<ViewPlannerEntry> table = builtin_view_planners();
  ASSERT_FALSE(table.empty());
  EXPECT_EQ(table.front().name, "ours");  // the paper's method, the default
  const std::vector<std::string> names = view_planner_names();
  ASSERT_GE(names.size(), table.size());
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(names[i], table[i].name);  // the registry starts with the table, in its order
    EXPECT_FALSE(table[i].description.empty());
    ViewPlannerSettings s;
    s.method.name = table[i].name;
    if (!table[i].reads_ground_truth) {
      EXPECT_EQ(table[i].make(s)->name(), table[i].name);
      continue;
    }
    // An oracle is declared here but built only by a context that holds the truth.
    EXPECT_NE(table[i].description.find("READS THE GROUND TRUTH"), std::string::npos) << table[i].name;
    try {
      table[i].make(s);
      ADD_FAILURE() << table[i].name << " built without a mission";
    } catch (const canopy::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("reads the ground truth"), std::string::npos) << e.what();
    }
  }
}
