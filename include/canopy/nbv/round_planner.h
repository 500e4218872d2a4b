#pragma once
// What the planners that plan one batch a round on the latest map share (reveal, shape, learned):
// the views of a stop that failed kept out of the rest of it (FailedViews), the start of a round,
// and the loop over candidates on spheres around each target through ours' reach test. Each
// planner scores the candidates its own way.
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/timer.h"
#include "canopy/nbv/candidates.h"
#include "canopy/nbv/failed_views.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv {

/// Every candidate on a sphere of each radius of `radii_m` around each of `centres` (target id:
/// the centre's index; `params`' other settings), in that order, passed to `each(candidate)`; the
/// sampling timed as `times`' "candidates" phase. The candidate set of reveal, shape and learned
/// (and of the oracle on learned's candidates).
template <class Each>
void for_each_sphere_candidate(const std::vector<Vec3>& centres, const std::vector<double>& radii_m,
                               CandidateParams params, PhaseTimes* times, Each&& each) {
  for (std::size_t i = 0; i < centres.size(); ++i)
    for (const double r : radii_m) {
      params.sphere.radius_m = r;
      std::vector<Candidate> cands;
      {
        ScopedPhase phase(*times, "candidates");
        cands = sample_candidates(centres[i], int(i), params);
      }
      for (Candidate& cand : cands) each(cand);
    }
}

class RoundPlanner : public ViewPlanner {
 public:
  void taken(const Pose& T) override {
    ViewPlanner::taken(T);
    failed_.taken(T);
  }

  void begin_stop() override { failed_.begin_stop(); }

 protected:
  explicit RoundPlanner(const ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), failed_(s.params.views), candidates_(s.params.candidates) {}

  /// A round on `req` begins: the last batch's views, none of which succeeded, join the failed
  /// ones; the batch returned is empty, its views to be tried in utility order.
  ViewBatch begin_round(const ViewRequest& req) {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    failed_.next_batch();
    ViewBatch batch;
    batch.order = BatchOrder::kUtility;
    return batch;
  }

  /// Every candidate on a sphere of each radius of `radii_m` around each of `centres` (target
  /// id: the centre's index; nbv.candidates' other settings), in that order, that may be offered
  /// (offerable: neither taken nor failed, reachable) passed to `score(candidate)` under the
  /// batch's "scoring" phase; the others counted in batch->filtered.
  template <class Score>
  void for_each_candidate(const std::vector<Vec3>& centres, const std::vector<double>& radii_m, const ViewRequest& req,
                          ViewBatch* batch, Score&& score) {
    for_each_sphere_candidate(centres, radii_m, candidates_, &batch->times, [&](Candidate& cand) {
      {
        ScopedPhase phase(batch->times, "filtering");
        if (!offerable(&cand, req, failed_)) {
          ++batch->filtered;
          return;
        }
      }
      ScopedPhase phase(batch->times, "scoring");
      score(cand);
    });
  }

  FailedViews failed_;

 private:
  CandidateParams candidates_;
};

}  // namespace canopy::nbv
