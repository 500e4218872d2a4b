// Dense predefined scanning (planners/predefined.h).

#include "canopy/nbv/planners/predefined.h"

namespace canopy::nbv::predefined {

namespace {

// Dense predefined scanning: the stop's scripted views, once, no planning.
class PredefinedPlanner : public ViewPlanner {
 public:
  explicit PredefinedPlanner(const ViewPlannerSettings& s) : ViewPlanner(s.params.views) {}
  std::string name() const override { return "predefined"; }
  PlannerTraits traits() const override {
    PlannerTraits t;
    t.scripted = true;
    t.execute_whole_batch = true;
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
    for (const Pose& T : req.scripted) {
      if (taken_.contains(T)) continue;
      PlannedView v;
      v.T_world_camera = T;
      v.target = T * Vec3(0, 0, 0.4);
      v.source = "predefined";
      batch.views.push_back(v);
    }
    batch.candidates = batch.views.size();
    if (batch.views.empty()) {
      batch.finished = true;
      batch.reason = "no predefined views";
    }
    return batch;
  }
  void begin_stop() override { served_ = false; }

 private:
  bool served_ = false;
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new PredefinedPlanner(settings));
}

}  // namespace canopy::nbv::predefined
