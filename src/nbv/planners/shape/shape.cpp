// The shape-completion planner (planners/shape/shape.h).

#include "canopy/nbv/planners/shape/shape.h"

#include <algorithm>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/nbv/fruit_shapes.h"
#include "canopy/nbv/planners/frontier/frontier.h"
#include "canopy/nbv/round_planner.h"

namespace canopy::nbv::shape {

namespace {

class ShapePlanner : public RoundPlanner {
 public:
  explicit ShapePlanner(const ViewPlannerSettings& s)
      : RoundPlanner(s), settings_(s), params_(s.params.planner<ShapeParams>()),
        uvc_(params_.uvc_weight > 0.0 ? make_gain("uvc", s.params.gain) : nullptr),
        fallback_(params_.fallback == "frontier" ? frontier::make_planner(s) : nullptr) {}

  std::string name() const override { return "shape"; }

  void taken(const Pose& T) override {
    RoundPlanner::taken(T);
    if (fallback_) fallback_->taken(T);
  }

  void outcome(const ViewOutcome& o) override {
    ViewPlanner::outcome(o);
    if (fallback_) fallback_->outcome(o);
  }

  void begin_stop() override {
    RoundPlanner::begin_stop();
    if (fallback_) fallback_->begin_stop();
  }

  // Shape's round; when it has nothing to offer and nbv.shape.fallback names a planner, that
  // planner's round on the same request instead (shape plans again first next round).
  ViewBatch next(const ViewRequest& req) override {
    ViewBatch batch = shape_round(req);
    if (!batch.views.empty() || !fallback_) return batch;
    ViewBatch fb = fallback_->next(req);
    fb.times.merge(batch.times);
    fb.clusters += batch.clusters;
    fb.candidates += batch.candidates;
    fb.filtered += batch.filtered;
    fb.reason = "shape: " + batch.reason + (fb.reason.empty() ? "" : "; " + params_.fallback + ": " + fb.reason);
    return fb;
  }

 private:
  ViewBatch shape_round(const ViewRequest& req) {
    ViewBatch batch = begin_round(req);
    std::vector<FittedFruit> fruits;
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      std::vector<Vec3> confirmed;
      fruits = fit_fruits(*req.map, settings_.params.cluster, params_.fit, &req.region, 0.1, &confirmed, &cache_);
      points_ = unseen_surface(fruits, confirmed, params_.spacing_m, params_.covered_m);
      weigh_points(*req.map, *req.index);
    }
    batch.clusters = fruits.size();
    if (fruits.empty() || points_.empty()) {
      batch.finished = true;
      batch.reason = fruits.empty() ? "no fruit clusters in reach" : "no predicted fruit surface left to see";
      return batch;
    }
    std::unique_ptr<ViewEvaluator> eval;
    if (uvc_) eval = std::make_unique<ViewEvaluator>(*req.index, settings_.intrinsics, settings_.params.rays);
    const RaySetEntry& rays = ray_set("ours");
    std::vector<ScoredView> scored;
    for_each_candidate(fitted_centres(fruits), params_.radii_m, req, &batch, [&](const Candidate& cand) {
      ScoredView sv{cand, {}};
      sv.score.gain = predicted_seen(*req.index, cand.T_world_camera);
      if (eval)
        sv.score.gain +=
            params_.uvc_weight * eval->evaluate(cand.T_world_camera, cand.target, *uvc_, rays, scored.size()).gain;
      if (req.on_scored) req.on_scored(sv);
      scored.push_back(sv);
    });
    take_best_views(std::move(scored), params_.max_views, "shape", "no candidate sees predicted fruit surface",
                    [this](const Pose& T) { failed_.offered(T); }, &batch);
    return batch;
  }

  // Still to be observed, with a weight: a predicted point in an unknown or an unconfirmed
  // fruit voxel counts 1; one in a voxel the map knows as free is refuted (the fit is off
  // there); one in another class's surface (a leaf covers it, or noise mislabelled the fruit)
  // is refuted, or counts the voxel's fruit probability among its occupied classes, as
  // nbv.shape.other_class says.
  void weigh_points(const mapping::SemanticOcTree& map, const VoxelIndex& index) {
    const int fruit = map.classes().target_index() + 1;  // prob[] holds free first
    const bool refute = params_.other_class == "refute";
    std::vector<PredictedPoint> kept;
    weights_.clear();
    for (const PredictedPoint& p : points_) {
      octomap::OcTreeKey k;
      if (!map.key_of(p.position, &k)) continue;
      const VoxelInfo& info = index.info(index.lookup(k));
      double w = 1.0;
      if (info.known && !info.is_target) {
        if (!(info.p_occ > 0.5f) || refute) continue;
        const double occupied = 1.0 - info.prob[0];
        w = occupied > 0.0 ? info.prob[fruit] / occupied : 0.0;
        if (!(w > 0.0)) continue;
      }
      kept.push_back(p);
      weights_.push_back(w);
    }
    points_ = std::move(kept);
  }

  // The unseen predicted points the view would see: in the image and depth range, facing the
  // camera, each weighted by its sight line's transmission (0 past an occupied voxel,
  // unknown_transmit per unknown one; the point's own voxel is not on it).
  double predicted_seen(const VoxelIndex& index, const Pose& T) {
    const CameraIntrinsics& K = settings_.intrinsics;
    const Pose T_inv = T.inverse();
    const Vec3 eye = T.translation();
    const double res = index.map()->getResolution();
    const std::size_t cap = index.max_voxels(K.max_range_m + 0.1);
    if (buffer_.size() < cap) buffer_.resize(cap);
    double sum = 0.0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const PredictedPoint& pp = points_[i];
      const Vec3& p = pp.position;
      const Vec3 to_eye = eye - p;
      if (to_eye.dot(pp.normal) <= 0.0) continue;  // the fruit's own far side
      const Vec3 c = T_inv * p;
      if (c.z() < K.min_range_m || c.z() > K.max_range_m) continue;
      double u = 0, v = 0;
      if (!K.project(c, &u, &v) || u < 0.0 || v < 0.0 || u >= K.width_px || v >= K.height_px) continue;
      const double dist = to_eye.norm();
      if (dist <= res) continue;
      const Vec3 end = p + to_eye * (res / dist);
      bool outside = false;
      const std::size_t m = index.cast(eye, end, p, buffer_.data(), buffer_.size(), &outside);
      if (outside) continue;
      double t = 1.0;
      for (std::size_t j = 0; j < m && t > 1e-3; ++j) {
        const VoxelInfo& info = *buffer_[j].info;
        if (!info.known) t *= params_.unknown_transmit;
        else if (info.p_occ > 0.5f) t = 0.0;
      }
      if (t > 1e-3) sum += t * weights_[i];
    }
    return sum;
  }

  ViewPlannerSettings settings_;
  ShapeParams params_;
  std::unique_ptr<GainFunction> uvc_;
  ShapeFitCache cache_;
  std::vector<PredictedPoint> points_;
  std::vector<double> weights_;  // per point of points_ (weigh_points)
  std::vector<RayVoxel> buffer_;
  std::unique_ptr<ViewPlanner> fallback_;  // nbv.shape.fallback, or null
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new ShapePlanner(settings));
}

ViewPlannerEntry entry() {
  return {"shape",
          "shape completion: every fruit cluster fitted with a spheroid, one view at a time scored by the "
          "predicted fruit surface it would newly see (docs/shape.md)",
          make_planner, false,
          planner_section<ShapeParams>("The shape-completion planner (method shape)")};
}

}  // namespace canopy::nbv::shape
