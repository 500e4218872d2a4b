// The planner on the learned view scorer (planners/learned/learned.h).

#include "canopy/nbv/planners/learned/learned.h"

#include <algorithm>
#include <numeric>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/nbv/round_planner.h"
#include "canopy/nbv/view_features.h"
#include "canopy/nbv/view_ranker.h"

namespace canopy::nbv::learned {

ViewFeatureParams feature_params(const LearnedParams& p) {
  ViewFeatureParams f;
  f.fit = p.fit;
  f.spacing_m = p.spacing_m;
  f.covered_m = p.covered_m;
  f.unknown_transmit = p.unknown_transmit;
  f.fruit_min_logodds = p.fruit_min_logodds;
  return f;
}

namespace {

class LearnedPlanner : public RoundPlanner {
 public:
  explicit LearnedPlanner(const ViewPlannerSettings& s)
      : RoundPlanner(s), params_(s.params.planner<LearnedParams>()), ranker_(find_data_file(params_.model)),
        features_(s.intrinsics, s.params, feature_params(params_)) {
    const auto& names = view_feature_names();
    seen_ = std::size_t(std::find(names.begin(), names.end(), "shape_in_view") - names.begin());
    unknown_ = std::size_t(std::find(names.begin(), names.end(), "uvc@ours") - names.begin());
    CANOPY_CHECK(seen_ < names.size() && unknown_ < names.size(), "the features name shape_in_view and uvc@ours");
  }

  std::string name() const override { return "learned"; }

  ViewBatch next(const ViewRequest& req) override {
    ViewBatch batch = begin_round(req);
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      features_.begin_round(*req.map, *req.index, req.region, req.T_world_camera);
    }
    const std::vector<FittedFruit>& fruits = features_.fruits();
    batch.clusters = fruits.size();
    if (fruits.empty()) {
      batch.finished = true;
      batch.reason = "no fruit clusters in reach";
      return batch;
    }
    const std::size_t width = view_feature_names().size();
    std::vector<Candidate> kept;
    std::vector<float> rows, f;
    for_each_candidate(fitted_centres(fruits), params_.radii_m, req, &batch, [&](const Candidate& cand) {
      features_.compute(cand.T_world_camera, cand.target, &f);
      ++batch.candidates;
      if (!(f[seen_] > 0.f) && !(f[unknown_] > 0.f)) return;  // nothing a view could add
      kept.push_back(cand);
      rows.insert(rows.end(), f.begin(), f.end());
    });
    if (kept.empty()) {
      batch.finished = true;
      batch.reason = batch.candidates == 0 ? "every candidate was filtered out"
                                           : "no candidate sees unseen fruit surface or unknown space";
      return batch;
    }
    std::vector<float> score;
    {
      ScopedPhase phase(batch.times, "scoring");
      std::vector<int> fruit;
      for (const Candidate& c : kept) fruit.push_back(c.cluster);
      score = ranker_.score(rows, kept.size(), fruit);
    }
    CANOPY_CHECK(rows.size() == kept.size() * width, "one feature row per kept candidate");
    std::vector<std::size_t> order(kept.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
    for (std::size_t i : order) {
      if (req.on_scored) req.on_scored(ScoredView{kept[i], ViewScore{score[i]}});
      if (int(batch.views.size()) >= params_.max_views) continue;
      batch.views.push_back(planned_view(kept[i], score[i], "learned"));
      failed_.offered(kept[i].T_world_camera);
    }
    return batch;
  }

 private:
  LearnedParams params_;
  ViewRanker ranker_;
  ViewFeatures features_;
  std::size_t seen_ = 0, unknown_ = 0;  // the features that say whether a view could add anything
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new LearnedPlanner(settings));
}

ViewPlannerEntry entry() {
  return {"learned",
          "a view scorer learned against the truth (gradient-boosted trees over map-only view features, "
          "trained on tuning worlds), one view at a time on the latest map (docs/learned.md)",
          make_planner, false, planner_section<LearnedParams>("The planner on the learned view scorer (method learned)")};
}

}  // namespace canopy::nbv::learned
