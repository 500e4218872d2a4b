// The candidate audit (mission/oracle/candidate_audit.h). READS THE GROUND TRUTH.

#include "canopy/mission/oracle/candidate_audit.h"

#include <utility>

#include "canopy/common/random.h"
#include "canopy/mission/oracle/oracle_planners.h"
#include "canopy/records/candidates_csv.h"
#include "canopy/nbv/planners/shape/shape_params.h"
#include "canopy/nbv/view_evaluator.h"

namespace canopy::mission {

namespace {

// The view features are computed as the shape planner fits and weighs fruit surface.
nbv::ViewFeatureParams feature_params(const settings::Settings& s) {
  const nbv::ShapeParams& shape = s.nbv.planner<nbv::ShapeParams>();
  nbv::ViewFeatureParams p;
  p.fit = shape.fit;
  p.spacing_m = shape.spacing_m;
  p.covered_m = shape.covered_m;
  p.unknown_transmit = shape.unknown_transmit;
  p.fruit_min_logodds = s.nbv.cluster.min_logodds;  // the training data's fruits (learned may plan with others)
  return p;
}

}  // namespace

CandidateAudit::CandidateAudit(const world::World& world, sim::Simulator& sim, const settings::Settings& settings)
    : world_(world), settings_(settings),
      scorer_(make_truth_scorer(sim, world.spec.camera, settings.mission.oracle)),
      features_(world.spec.camera, settings.nbv, feature_params(settings)) {
  scorer_->cache_views(evaluation::target_surface_points(world.truth));
  for (const records::AuditScore& s : records::audit_scores()) {
    nbv::GainParams gp = settings.nbv.gain;
    if (s.sets_proximity) gp.proximity = s.proximity;
    gains_.push_back(nbv::make_gain(s.gain->name, gp, "audit"));
  }
}

nbv::CandidateObserver CandidateAudit::observer() {
  pending_.clear();
  return [this](const nbv::ScoredView& v) { pending_.push_back(v); };
}

void CandidateAudit::end_round(const mapping::SemanticOcTree& map, const nbv::VoxelIndex& index,
                               const nbv::ViewBatch& batch, int stop, int round, int views_before, std::uint64_t seed,
                               const Eigen::AlignedBox3d& region, const Pose& T_world_camera) {
  if (pending_.empty()) return;
  features_.begin_round(map, index, region, T_world_camera);
  if (stop != scorer_stop_) {  // the truth scene stands still within a stop: a pose is rendered once
    scorer_->forget_views();
    scorer_stop_ = stop;
  }
  scorer_->set_points(evaluation::uncovered_target_points(map, world_.truth, settings_.mapping.metrics));
  nbv::ViewEvaluator eval(index, world_.spec.camera, settings_.nbv.rays);
  const nbv::RaySetEntry& rays = nbv::ray_set(settings_.method.rays, "method.rays");
  const Pose* chosen = batch.views.empty() ? nullptr : &batch.views.front().T_world_camera;
  bool chosen_marked = false;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const nbv::ScoredView& v = pending_[i];
    records::CandidateRecord r;
    r.stop = stop;
    r.round = round;
    r.views_before = views_before;
    r.cluster = v.candidate.cluster;
    r.T_world_camera = v.candidate.T_world_camera;
    r.planner_gain = v.score.gain;
    if (chosen && !chosen_marked && r.T_world_camera.isApprox(*chosen, 1e-12)) r.chosen = chosen_marked = true;
    r.frustum = scorer_->in_frustum(r.T_world_camera);
    r.truth = scorer_->visible(r.T_world_camera);
    for (const auto& g : gains_)
      r.scores.push_back(eval.evaluate(v.candidate.T_world_camera, v.candidate.target, *g, rays, mix_seed(seed, i)).gain);
    features_.compute(v.candidate.T_world_camera, v.candidate.target, &r.features);
    records_.push_back(std::move(r));
  }
  pending_.clear();
}

}  // namespace canopy::mission
