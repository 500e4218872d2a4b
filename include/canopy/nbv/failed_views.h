#pragma once
// The views of a planner's last batch that the mission did not take. The mission tries a batch
// in order until one view succeeds: the views before the one taken failed, and when the next
// batch is asked for, none of the last one succeeded. Planners that plan one batch per round on
// the latest map (reveal, the oracles) keep such views out of the rest of the stop.
#include <vector>

#include "canopy/nbv/view_planner.h"

namespace canopy::nbv {

class FailedViews {
 public:
  explicit FailedViews(const ViewRules& rules) : rules_(rules), failed_(rules) {}

  /// A view of the batch being returned, in the order the mission will try it.
  void offered(const Pose& T) { pending_.push_back(T); }
  /// The mission reached T: the offered views before it failed. A reached camera lies within
  /// the execution tolerance of its goal, so the goal is matched within 3 cm / 10 deg.
  void taken(const Pose& T) {
    ViewRules loose;
    loose.taken_position_m = 0.03;
    loose.taken_angle_deg = 10.0;
    TakenViews reached(loose);
    reached.add(T);
    for (const Pose& p : pending_) {
      if (reached.contains(p)) break;
      failed_.add(p);
    }
    pending_.clear();
  }
  /// A new batch is asked for: nothing of the last one succeeded.
  void next_batch() {
    for (const Pose& p : pending_) failed_.add(p);
    pending_.clear();
  }
  void begin_stop() {
    failed_ = TakenViews(rules_);
    pending_.clear();
  }
  bool contains(const Pose& T) const { return failed_.contains(T); }

 private:
  ViewRules rules_;
  TakenViews failed_;
  std::vector<Pose> pending_;
};

}  // namespace canopy::nbv
