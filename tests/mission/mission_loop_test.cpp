// The mission loop's accounting on the small world: every stop meets its budget of successful
// views or says why not, the attempt cap counts attempts whatever the planner's batch size,
// every attempt's outcome reaches the planner, and a stop request ends a loop of attempts that
// never step the simulator. In a binary of its own: it registers a test planner, which the
// registry's name lists would show to the other mission tests.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "canopy/mission/mission.h"
#include "canopy/records/run_folder.h"
#include "canopy/world/world_spec.h"

namespace canopy::mission {

// The records the mission fills in and the settings it reads, by their short names.
using namespace canopy::records;
using namespace canopy::settings;
namespace {

struct SmallWorld {
  world::World world;
  Settings settings;
  SmallWorld() : world(world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")))),
                 settings(Settings::defaults(default_robot_config())) {
    settings.mapping.extractor.source = perception::LabelSource::kTruth;
    settings.mapping.extractor.p_gt = 1.0;
    settings.mission.stops.count = 1;
    settings.mission.loop.views_per_stop = 3;
  }
};

const SmallWorld& small() {
  static const SmallWorld w;
  return w;
}

// Every stop executes its budget of successful views (the initial scan's 12 and
// views_per_stop more) unless the planner says it has nothing left or the attempts are spent;
// summary.json says which, per stop.
TEST(MissionLoop, EveryStopMeetsItsBudgetOrSaysWhyNot) {
  const SmallWorld& w = small();
  for (const char* method : {"ours", "frontier", "reveal"}) {
    SCOPED_TRACE(method);
    Settings s = w.settings;
    s.method.name = method;
    s.mission.loop.views_per_stop = 4;
    Mission mission(w.world, s, 1);
    const MissionResult r = mission.run();
    ASSERT_TRUE(r.complete);
    const nlohmann::json j = summary_json(r);
    int total = 0;
    for (std::size_t k = 0; k < r.stops.size(); ++k) {
      const StopRecord& st = r.stops[k];
      const int ok = st.initial_ok + st.nbv_ok;
      total += ok;
      EXPECT_EQ(st.budget, 12 + 4);
      EXPECT_EQ(j["stops"][k]["budget"], st.budget);
      EXPECT_EQ(j["stops"][k]["successful"], ok);
      EXPECT_EQ(j["stops"][k]["end"], st.end);
      // The exploration planner fills the rounds a method has nothing for: every stop takes its budget.
      EXPECT_EQ(st.end, "budget_met") << st.end_reason;
      EXPECT_EQ(ok, st.budget);
      EXPECT_LE(st.nbv_attempted, s.mission.loop.max_attempts);
    }
    EXPECT_EQ(total, r.successful_views());
    int running = 0;
    for (const ViewRecord& v : r.views) EXPECT_EQ(v.successful_views, running += v.success);
  }
}

// A planner that floods the mission with views far out of reach and records what it is told.
struct Flood {
  static std::vector<nbv::ViewOutcome>& told() {
    static std::vector<nbv::ViewOutcome> t;
    return t;
  }
  static std::size_t& batches() {
    static std::size_t n = 0;
    return n;
  }
};
class FloodPlanner : public nbv::ViewPlanner {
 public:
  FloodPlanner() : ViewPlanner(nbv::ViewRules{}) {}
  std::string name() const override { return "test_flood"; }
  nbv::ViewBatch next(const nbv::ViewRequest&) override {
    ++Flood::batches();
    nbv::ViewBatch b;
    for (int i = 0; i < 100000; ++i) {
      nbv::PlannedView v;
      v.T_world_camera.translation() = Vec3(50.0 + i, 0.0, 1.0);  // no IK
      v.source = "flood";
      b.views.push_back(v);
    }
    return b;
  }
  void outcome(const nbv::ViewOutcome& o) override {
    ViewPlanner::outcome(o);
    Flood::told().push_back(o);
  }
};

void register_flood() {
  static const bool once = [] {
    nbv::register_view_planner({"test_flood", "a test planner that returns 10^5 unreachable views",
                                [](const nbv::ViewPlannerSettings&) { return std::make_unique<FloodPlanner>(); }});
    return true;
  }();
  (void)once;
}

// The cap counts attempts, whatever the batch size (a planner returning 10^5 views is cut to
// the attempts left before the tour); every attempt's outcome reaches the planner; a mission
// most of whose attempts fail says so in its end reason.
TEST(MissionLoop, TheAttemptCapBoundsAFloodAndThePlannerLearnsEveryOutcome) {
  register_flood();
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "test_flood";
  s.mission.loop.max_attempts = 20;
  Flood::told().clear();
  Flood::batches() = 0;
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  const StopRecord& st = r.stops.at(0);
  EXPECT_EQ(st.nbv_attempted, 20);
  EXPECT_EQ(st.end, "attempt_cap");
  EXPECT_EQ(Flood::batches(), 1u);
  ASSERT_EQ(Flood::told().size(), r.views.size());
  for (std::size_t i = 0; i < r.views.size(); ++i) {
    const nbv::ViewOutcome& o = Flood::told()[i];
    EXPECT_EQ(o.attempt, r.views[i].attempt);
    EXPECT_EQ(o.success, r.views[i].success);
    EXPECT_EQ(o.failure, to_string(r.views[i].failure));
    if (o.phase == "nbv") {
      EXPECT_EQ(o.failure, to_string(FailureCause::kNoIk));
      EXPECT_EQ(o.view.source, "flood");
      EXPECT_FALSE(o.detail.empty());
    }
  }
  EXPECT_EQ(r.successful_views(), 12);
  EXPECT_NE(r.end_reason.find("most attempts failed (20 of 32: no_ik 20)"), std::string::npos) << r.end_reason;
  EXPECT_NE(summary_json(r)["end_reason"].get<std::string>().find("most attempts failed"), std::string::npos);
}

// A planner that ends every stop at once, and one that offers the same unreachable view every
// round (it never looks at failed_views()): what the mission guarantees whatever the planner.
struct Stubborn {
  static std::size_t& rounds() {
    static std::size_t n = 0;
    return n;
  }
};
class DonePlanner : public nbv::ViewPlanner {
 public:
  DonePlanner() : ViewPlanner(nbv::ViewRules{}) {}
  std::string name() const override { return "test_done"; }
  nbv::ViewBatch next(const nbv::ViewRequest&) override {
    nbv::ViewBatch b;
    b.finished = true;
    b.reason = "a test planner with nothing to see";
    return b;
  }
};
class StubbornPlanner : public nbv::ViewPlanner {
 public:
  StubbornPlanner() : ViewPlanner(nbv::ViewRules{}) {}
  std::string name() const override { return "test_stubborn"; }
  nbv::ViewBatch next(const nbv::ViewRequest&) override {
    ++Stubborn::rounds();
    nbv::ViewBatch b;
    nbv::PlannedView v;
    v.T_world_camera.translation() = Vec3(50.0, 0.0, 1.0);  // no IK: fails for a cause of its own
    v.source = "stubborn";
    b.views.push_back(v);
    return b;
  }
};

void register_done_and_stubborn() {
  static const bool once = [] {
    nbv::register_view_planner({"test_done", "a test planner that ends every stop at once",
                                [](const nbv::ViewPlannerSettings&) { return std::make_unique<DonePlanner>(); }});
    nbv::register_view_planner({"test_stubborn", "a test planner that offers one failing view every round",
                                [](const nbv::ViewPlannerSettings&) { return std::make_unique<StubbornPlanner>(); }});
    return true;
  }();
  (void)once;
}

// The mission, not the planner, keeps the stop's budget: a method with nothing to see gets
// the exploration planner's views (frontier's, tagged by frontier), and with
// mission.loop.exploration none the stop ends with the method.
TEST(MissionLoop, TheExplorationPlannerFillsTheBudgetOfAMethodWithNothingLeft) {
  register_done_and_stubborn();
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "test_done";
  {
    Mission mission(w.world, s, 1);
    const MissionResult r = mission.run();
    const StopRecord& st = r.stops.at(0);
    EXPECT_EQ(st.end, "budget_met") << st.end_reason;
    EXPECT_EQ(st.initial_ok + st.nbv_ok, st.budget);
    EXPECT_GE(st.exploration_rounds, 1);
    EXPECT_EQ(summary_json(r)["stops"][0]["exploration_rounds"], st.exploration_rounds);
    for (const ViewRecord& v : r.views) {
      if (v.phase != ViewPhase::kNbv) continue;
      EXPECT_TRUE(v.source == "roi" || v.source == "exploration") << v.source;
    }
  }
  s.mission.loop.exploration = "none";
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  const StopRecord& st = r.stops.at(0);
  EXPECT_EQ(st.end, "planner_done");
  EXPECT_EQ(st.nbv_attempted, 0);
  EXPECT_EQ(st.exploration_rounds, 0);
  EXPECT_NE(st.end_reason.find("a test planner with nothing to see"), std::string::npos) << st.end_reason;
}

// A view that failed for a cause of its own is attempted once per stop, whatever the planner
// offers: the mission drops it (counted as guarded), and the exploration planner fills the round.
TEST(MissionLoop, AViewThatFailedIsNeverAttemptedAgainAtTheStop) {
  register_done_and_stubborn();
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "test_stubborn";
  Stubborn::rounds() = 0;
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  const StopRecord& st = r.stops.at(0);
  int stubborn = 0;
  for (const ViewRecord& v : r.views) stubborn += v.source == "stubborn";
  EXPECT_EQ(stubborn, 1);
  EXPECT_EQ(st.guarded, static_cast<int>(Stubborn::rounds()) - 1);
  EXPECT_GE(st.guarded, 1);
  EXPECT_EQ(st.end, "budget_met") << st.end_reason;
  EXPECT_EQ(summary_json(r)["guarded"], st.guarded);
  // Without an exploration planner the rounds are idle until max_idle_rounds.
  s.mission.loop.exploration = "none";
  s.mission.loop.max_idle_rounds = 3;
  Stubborn::rounds() = 0;
  Mission alone(w.world, s, 1);
  const MissionResult a = alone.run();
  stubborn = 0;
  for (const ViewRecord& v : a.views) stubborn += v.source == "stubborn";
  EXPECT_EQ(stubborn, 1);
  EXPECT_EQ(a.stops.at(0).end, "idle_rounds") << a.stops.at(0).end_reason;
  EXPECT_EQ(a.stops.at(0).guarded, 3);
}

// Ctrl-C between attempts that never step the simulator (views without IK) ends the mission.
TEST(MissionLoop, AStopRequestEndsALoopOfUnreachableViews) {
  register_flood();
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "test_flood";
  s.mission.loop.max_attempts = 100000;
  Flood::told().clear();
  MissionCallbacks cb;
  cb.stop_requested = [] { return Flood::told().size() >= 30; };
  Mission mission(w.world, s, 1, cb);
  const MissionResult r = mission.run();
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(r.views.size(), 30u);
  EXPECT_EQ(r.stops.at(0).end, "interrupted");
  EXPECT_EQ(r.end_reason.rfind("interrupted", 0), 0u) << r.end_reason;
}

}  // namespace
}  // namespace canopy::mission
