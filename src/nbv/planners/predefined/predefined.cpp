// Dense predefined scanning (planners/predefined/predefined.h).

#include "canopy/nbv/planners/predefined/predefined.h"

#include <algorithm>

namespace canopy::nbv::predefined {

namespace {

// Dense predefined scanning: the stop's scripted views, once, no planning.
class PredefinedPlanner : public ViewPlanner {
 public:
  explicit PredefinedPlanner(const ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), params_(s.params.planner<PredefinedParams>()) {}
  std::string name() const override { return "predefined"; }
  PlannerTraits traits() const override {
    PlannerTraits t;
    t.scripted = true;
    t.execute_whole_batch = true;
    t.replaces_failed = true;
    return t;
  }
  ViewBatch next(const ViewRequest& req) override {
    ViewBatch batch;
    batch.order = BatchOrder::kTour;
    batch.last_of_stop = true;
    batch.reason = "predefined views done";
    if (served_) {
      batch.finished = true;
      batch.reason = "every predefined view of this stop was tried";
      return batch;
    }
    served_ = true;
    const bool test = params_.goal_test_at_planning && req.goal_free;
    const Stopwatch filtering;
    for (const Pose& T : req.scripted) {
      if (taken_.contains(T)) continue;
      PlannedView v;
      v.T_world_camera = T;
      v.target = T * Vec3(0, 0, 0.4);
      v.source = "predefined";
      ++batch.candidates;
      if (test && !req.goal_free(v)) {  // would fail before the arm moves: replaced instead
        ++batch.filtered;
        batch.refused.push_back(v);
        continue;
      }
      batch.views.push_back(v);
    }
    if (test) batch.times.add("filtering", filtering.seconds());
    if (batch.views.empty() && batch.refused.empty()) {
      batch.finished = true;
      batch.reason = "no predefined views";
    }
    return batch;
  }
  void begin_stop() override {
    served_ = false;
    replacements_.clear();
  }

  // The nearest option first; views without IK at this base are skipped (not attempted), a
  // scripted view or a replacement tried before at this stop is never repeated, and at most
  // max_attempts are attempted, until one succeeds.
  bool replace_failed(const FailedScriptedView& req) override {
    int tries = 0;
    for (const PlannedView& v : req.options) {
      if (tries >= req.max_attempts || (req.attempts_left && *req.attempts_left <= 0)) break;
      const auto same = [&](const Pose& u) { return same_view(u, v.T_world_camera); };
      if (std::any_of(req.scripted.begin(), req.scripted.end(), same) ||
          std::any_of(replacements_.begin(), replacements_.end(), same))
        continue;
      if (req.reachable && !req.reachable(v)) continue;
      replacements_.push_back(v.T_world_camera);
      ++tries;
      if (req.attempt(v)) return true;
    }
    return false;
  }

 private:
  PredefinedParams params_;
  bool served_ = false;
  std::vector<Pose> replacements_;  // replacements tried at this stop
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new PredefinedPlanner(settings));
}

ViewPlannerEntry entry() {
  return {"predefined",
          "dense predefined scanning: the scripted views of every stop, no planning",
          make_planner, false,
          planner_section<PredefinedParams>("Dense predefined scanning (method predefined)")};
}

}  // namespace canopy::nbv::predefined
