// The oracle planners (mission/oracle/oracle_planners.h). READ THE GROUND TRUTH.

#include "canopy/mission/oracle/oracle_planners.h"

#include <algorithm>
#include <functional>
#include <mutex>

#include "canopy/common/error.h"
#include "canopy/common/view_sphere.h"
#include "canopy/mission/mission.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/failed_views.h"
#include "canopy/nbv/fruit_shapes.h"
#include "canopy/nbv/planners/learned/learned.h"
#include "canopy/nbv/planners/ours/ours.h"
#include "canopy/nbv/round_planner.h"
#include "canopy/nbv/view_features.h"
#include "canopy/sim/renderer.h"

namespace canopy::mission {

std::unique_ptr<evaluation::TruthViewScorer> make_truth_scorer(sim::Simulator& sim, const CameraIntrinsics& camera,
                                                               const settings::OracleParams& params) {
  const CameraIntrinsics K = evaluation::truth_render_intrinsics(camera, params.render_downsample);
  auto renderer = std::make_shared<sim::Renderer>(sim, K, sim::RenderOptions{false, 1, false});
  return std::make_unique<evaluation::TruthViewScorer>(K, params.depth_tolerance_m, [renderer](const Pose& T) {
    return renderer->render_depth(T);  // render(T, false, false).depth_m, bit for bit
  });
}

namespace {

// One candidate of an oracle round with its truth score.
struct TruthView {
  nbv::Candidate candidate;
  std::size_t bound = 0;   // points in its frustum
  std::size_t score = 0;   // points it sees
};

class OraclePlanner : public nbv::ViewPlanner {
 public:
  OraclePlanner(const nbv::ViewPlannerSettings& s, const MissionContext* context, bool any)
      : ViewPlanner(s.params.views), settings_(s), any_(any), context_(context),
        learned_set_(!any && context->oracle.candidates == "learned"), done_(s.params.views), failed_(s.params.views) {
    if (!context_->world || !context_->sim)
      throw InputError(std::string("method ") + name() + " reads the ground truth: its mission has no world");
  }

  std::string name() const override { return any_ ? "oracle_any" : "oracle"; }

  void taken(const Pose& T) override {
    ViewPlanner::taken(T);
    failed_.taken(T);
  }
  void begin_stop() override {
    failed_.begin_stop();
    // The truth scene stands still within a stop: each pose is rendered once per stop.
    if (scorer_) scorer_->forget_views();
  }

  nbv::ViewBatch next(const nbv::ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    const settings::OracleParams& op = context_->oracle;
    if (!scorer_) {
      scorer_ = make_truth_scorer(*context_->sim, settings_.intrinsics, op);
      scorer_->cache_views(evaluation::target_surface_points(context_->world->truth));
    }
    failed_.next_batch();
    nbv::ViewBatch batch;
    batch.order = nbv::BatchOrder::kUtility;
    {
      ScopedPhase phase(batch.times, "truth");
      scorer_->set_points(evaluation::uncovered_target_points(*req.map, context_->world->truth, context_->metrics));
    }
    std::vector<TruthView> views = any_            ? dense_views(req, &batch)
                                   : learned_set_ ? learned_views(req, &batch)
                                                  : ours_views(req, &batch);
    if (views.empty()) {
      batch.finished = true;
      if (batch.reason.empty()) batch.reason = "no candidate left";
      return batch;
    }
    // The best views by the truth (branch and bound); oracle_any's reach test runs only on
    // the views it renders.
    std::vector<evaluation::TruthScore> best;
    {
      ScopedPhase phase(batch.times, "scoring");
      std::vector<Pose> poses;
      for (const TruthView& v : views) poses.push_back(v.candidate.T_world_camera);
      std::function<bool(std::size_t, Pose*)> accept;
      if (any_)
        accept = [&](std::size_t i, Pose* pose) {
          if (!reachable(req, &views[i])) return false;
          *pose = views[i].candidate.T_world_camera;
          return true;
        };
      std::vector<std::size_t> bounds;
      best = evaluation::best_truth_views(*scorer_, &poses, std::size_t(op.max_views), accept, &bounds);
      for (std::size_t i = 0; i < views.size(); ++i) views[i].bound = bounds[i];
    }
    for (const evaluation::TruthScore& t : best)
      batch.views.push_back(nbv::planned_view(views[t.view].candidate, double(t.score), any_ ? "oracle_any" : "oracle"));
    for (const nbv::PlannedView& v : batch.views) failed_.offered(v.T_world_camera);
    if (!any_ && !learned_set_) mark_done(views);
    batch.finished = batch.views.empty();
    if (batch.finished) batch.reason = "no candidate sees an uncovered fruit point (ground truth)";
    return batch;
  }

 private:
  // ours' candidates, selected by ours' own functions: clusters of the map (minus done ones),
  // the sphere around each, the taken-view rule and the reach test; and no view that failed.
  std::vector<TruthView> ours_views(const nbv::ViewRequest& req, nbv::ViewBatch* batch) {
    std::vector<TruthView> out;
    clusters_ = nbv::ours::open_clusters(req, settings_.params.cluster, done_, batch);
    if (clusters_.empty()) return out;
    ScopedPhase phase(batch->times, "filtering");
    const nbv::CandidateFilter ours_filter = nbv::ours::candidate_filter(req, taken_);
    const nbv::CandidateFilter filter = [&](nbv::Candidate* c) {
      return ours_filter(c) && !failed_.contains(c->T_world_camera);
    };
    for (std::size_t c = 0; c < clusters_.size(); ++c)
      for (const nbv::KeptCandidate& k :
           nbv::ours_candidates(clusters_[c], int(c), settings_.params.candidates, filter, &batch->filtered))
        out.push_back({k.candidate, 0, 0});
    batch->candidates = out.size();
    return out;
  }

  // learned's candidates (planners/learned): spheres of nbv.learned.radii_m around the fitted
  // centres of the stop's fruits (the shape fit of nbv.learned.fit over the voxels above
  // nbv.learned.fruit_min_logodds), neither taken nor failed
  // and reachable; no map test of what a view could add (the truth decides).
  std::vector<TruthView> learned_views(const nbv::ViewRequest& req, nbv::ViewBatch* batch) {
    const nbv::LearnedParams& lp = settings_.params.planner<nbv::LearnedParams>();
    const nbv::ViewFeatureParams fp = nbv::learned::feature_params(lp);  // the fruits learned finds
    std::vector<nbv::FittedFruit> fruits;
    {
      ScopedPhase phase(batch->times, "clustering");
      fruits = nbv::fit_fruits(*req.map, fp.clustering(settings_.params.cluster), fp.fit, &req.region, fp.margin_m,
                               nullptr, &fits_);
    }
    batch->clusters = fruits.size();
    std::vector<TruthView> out;
    nbv::for_each_sphere_candidate(nbv::fitted_centres(fruits), lp.radii_m, settings_.params.candidates, &batch->times,
                                   [&](nbv::Candidate& c) {
                                     ScopedPhase phase(batch->times, "filtering");
                                     if (offerable(&c, req, failed_))
                                       out.push_back({c, 0, 0});
                                     else
                                       ++batch->filtered;
                                   });
    batch->candidates = out.size();
    if (fruits.empty()) batch->reason = "no fruit clusters in reach";
    return out;
  }

  // A cluster whose candidates' frustums hold no uncovered point is done (its views are scored
  // only while their bound can win, so a zero bound is the proof).
  void mark_done(const std::vector<TruthView>& views) {
    std::vector<std::size_t> bound(clusters_.size(), 0);
    std::vector<bool> seen(clusters_.size(), false);
    for (const TruthView& v : views) {
      const auto c = std::size_t(v.candidate.cluster);
      bound[c] = std::max(bound[c], v.bound);
      seen[c] = true;
    }
    for (std::size_t c = 0; c < clusters_.size(); ++c)
      if (!seen[c] || bound[c] == 0) done_.mark(clusters_[c].centroid);
  }

  // The dense set: spheres of several radii around every target fruit of the stop that still
  // has uncovered points; positions the workspace holds, views not taken, the any_scored with
  // the largest frustum bound.
  std::vector<TruthView> dense_views(const nbv::ViewRequest& req, nbv::ViewBatch* batch) {
    const settings::OracleParams& op = context_->oracle;
    std::vector<int> open;
    for (const evaluation::UncoveredPoint& p : scorer_->points())
      if (open.empty() || open.back() != p.instance_id) open.push_back(p.instance_id);
    std::vector<TruthView> out;
    ScopedPhase phase(batch->times, "candidates");
    int target = 0;
    for (const world::FruitTruth& f : context_->world->truth.fruits) {
      if (!f.target || std::find(open.begin(), open.end(), f.instance_id) == open.end()) continue;
      if (!req.region.contains(f.center)) continue;
      for (const double r : op.any_radii_m) {
        ViewSphere sphere;
        sphere.radius_m = r;
        sphere.polar_count = op.any_polar_count;
        sphere.azimuth_count = op.any_azimuth_count;
        for (const SphereView& sv : sphere_views(f.center, sphere)) {
          nbv::Candidate c;
          c.T_world_camera = sv.T_world_camera;
          c.target = f.center;
          c.cluster = target;
          c.polar_deg = sv.polar_deg;
          c.azimuth_deg = sv.azimuth_deg;
          if (c.T_world_camera.translation().z() < settings_.params.candidates.min_height_m) continue;
          if (req.in_workspace && !req.in_workspace(c.T_world_camera.translation())) {
            ++batch->filtered;
            continue;
          }
          if (taken_.contains(c.T_world_camera) || failed_.contains(c.T_world_camera)) continue;
          out.push_back({c, 0, 0});
        }
      }
      ++target;
    }
    batch->clusters = std::size_t(target);
    batch->candidates = out.size();
    if (out.empty()) batch->reason = "no fruit of the stop with uncovered points in the workspace (ground truth)";
    // Keep the any_scored views with the largest frustum bound.
    for (TruthView& v : out) v.bound = scorer_->in_frustum(v.candidate.T_world_camera);
    std::stable_sort(out.begin(), out.end(), [](const TruthView& a, const TruthView& b) { return a.bound > b.bound; });
    if (out.size() > std::size_t(op.any_scored)) out.resize(std::size_t(op.any_scored));
    return out;
  }

  // The reach test of oracle_any's views (it may move them); false drops the view.
  bool reachable(const nbv::ViewRequest& req, TruthView* v) {
    if (req.reach && !req.reach(&v->candidate)) return false;
    return !taken_.contains(v->candidate.T_world_camera) && !failed_.contains(v->candidate.T_world_camera);
  }

  nbv::ViewPlannerSettings settings_;
  bool any_;
  const MissionContext* context_ = nullptr;
  bool learned_set_ = false;  // oracle (not oracle_any) on learned's candidates: mission.oracle.candidates
  nbv::DoneClusters done_;
  nbv::FailedViews failed_{nbv::ViewRules{}};
  std::vector<nbv::Cluster> clusters_;
  nbv::ShapeFitCache fits_;
  std::unique_ptr<evaluation::TruthViewScorer> scorer_;
};

}  // namespace

std::unique_ptr<nbv::ViewPlanner> make_oracle_planner(const std::string& name, const nbv::ViewPlannerSettings& s,
                                                      const MissionContext& context) {
  if (name != "oracle" && name != "oracle_any") return nullptr;
  return std::make_unique<OraclePlanner>(s, &context, name == "oracle_any");
}

}  // namespace canopy::mission
