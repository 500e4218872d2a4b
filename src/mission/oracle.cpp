// The oracle planners and the truth scorer (mission/oracle.h). READS THE GROUND TRUTH.

#include "canopy/mission/oracle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <numeric>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/common/view_sphere.h"
#include "canopy/mission/mission.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/failed_views.h"

namespace canopy::mission {

namespace {

CameraIntrinsics coarse(const CameraIntrinsics& K, int downsample) {
  CameraIntrinsics c = K;
  const double f = 1.0 / double(std::max(1, downsample));
  c.width_px = std::max(1, int(K.width_px * f));
  c.height_px = std::max(1, int(K.height_px * f));
  c.fx_px = K.fx_px * f;
  c.fy_px = K.fy_px * f;
  c.cx_px = K.cx_px * f;
  c.cy_px = K.cy_px * f;
  c.depth_noise_k = 0.0;
  return c;
}

}  // namespace

TruthViewScorer::TruthViewScorer(sim::Simulator& sim, const CameraIntrinsics& camera, int downsample,
                                 double depth_tolerance_m)
    : camera_(camera), intrinsics_(coarse(camera, downsample)), tolerance_m_(depth_tolerance_m),
      renderer_(sim, intrinsics_, sim::RenderOptions{false, 1, false}) {}

void TruthViewScorer::set_points(std::vector<evaluation::UncoveredPoint> points) { points_ = std::move(points); }

std::size_t TruthViewScorer::in_frustum(const Pose& T) const {
  const Pose T_inv = T.inverse();
  std::size_t n = 0;
  for (const evaluation::UncoveredPoint& p : points_) {
    const Vec3 c = T_inv * p.position;
    if (c.z() < intrinsics_.min_range_m || c.z() > intrinsics_.max_range_m) continue;
    double u = 0, v = 0;
    if (intrinsics_.project(c, &u, &v) && u >= 0.0 && v >= 0.0 && u < intrinsics_.width_px && v < intrinsics_.height_px)
      ++n;
  }
  return n;
}

std::size_t TruthViewScorer::visible(const Pose& T) {
  if (in_frustum(T) == 0) return 0;
  const LabelledFrame f = renderer_.render(T, /*show_robot=*/false, /*labels=*/false);
  ++renders_;
  const Pose T_inv = T.inverse();
  std::size_t n = 0;
  for (const evaluation::UncoveredPoint& p : points_) {
    const Vec3 c = T_inv * p.position;
    if (c.z() < intrinsics_.min_range_m || c.z() > intrinsics_.max_range_m) continue;
    double u = 0, v = 0;
    if (!intrinsics_.project(c, &u, &v) || u < 0.0 || v < 0.0 || u >= intrinsics_.width_px || v >= intrinsics_.height_px)
      continue;
    const float d = f.depth_m.at(int(u), int(v));
    if (!(d > 0.f)) continue;
    // A pixel spans z / fx metres; a slanted surface changes depth by about that much across it.
    const double tol = tolerance_m_ + 1.5 * c.z() / intrinsics_.fx_px;
    if (c.z() <= double(d) + tol) ++n;
  }
  return n;
}

std::vector<TruthScore> best_truth_views(TruthViewScorer& scorer, std::vector<Pose>* views, std::size_t keep,
                                         const std::function<bool(std::size_t, Pose*)>& accept) {
  std::vector<TruthScore> all(views->size());
  for (std::size_t i = 0; i < views->size(); ++i) all[i] = {i, scorer.in_frustum((*views)[i]), 0};
  std::vector<TruthScore> order = all;
  std::stable_sort(order.begin(), order.end(), [](const TruthScore& a, const TruthScore& b) { return a.bound > b.bound; });
  std::vector<TruthScore> best;  // best first, ties by view index
  auto better = [](const TruthScore& a, const TruthScore& b) {
    return a.score > b.score || (a.score == b.score && a.view < b.view);
  };
  for (TruthScore t : order) {
    if (keep == 0) break;
    const std::size_t floor_score = best.size() >= keep ? best[keep - 1].score : 0;
    // A bound equal to the floor can still tie it, and an earlier view wins a tie.
    if (t.bound == 0 || t.bound < floor_score || (t.bound == floor_score && best.size() >= keep && t.view > best[keep - 1].view))
      continue;
    Pose& pose = (*views)[t.view];
    if (accept) {
      if (!accept(t.view, &pose)) continue;
      t.bound = scorer.in_frustum(pose);
    }
    t.score = scorer.visible(pose);
    if (t.score == 0) continue;
    best.insert(std::upper_bound(best.begin(), best.end(), t, better), t);
    if (best.size() > keep) best.pop_back();
  }
  return best;
}

std::vector<std::string> audit_score_names() {
  return {"osamcep_per_voxel", "osamcep_per_segment_end", "ae", "uvc", "uvpc", "oae", "mi", "rs"};
}

CandidateAudit::CandidateAudit(const world::World& world, sim::Simulator& sim, const Settings& settings)
    : world_(world), settings_(settings),
      scorer_(sim, world.spec.camera, settings.mission.oracle.render_downsample, settings.mission.oracle.depth_tolerance_m) {
  for (const std::string& name : audit_score_names()) {
    nbv::GainParams gp = settings.nbv.gain;
    std::string gain = name;
    if (name == "osamcep_per_voxel" || name == "osamcep_per_segment_end") {
      gp.proximity = name == "osamcep_per_voxel" ? nbv::Proximity::kPerVoxel : nbv::Proximity::kPerSegmentEnd;
      gain = "osamcep";
    }
    gains_.push_back(nbv::make_gain(gain, gp, "audit"));
  }
}

nbv::CandidateObserver CandidateAudit::observer() {
  pending_.clear();
  return [this](const nbv::ScoredView& v) { pending_.push_back(v); };
}

void CandidateAudit::end_round(const mapping::SemanticOcTree& map, const nbv::VoxelIndex& index,
                               const nbv::ViewBatch& batch, int stop, int round, int views_before, std::uint64_t seed) {
  if (pending_.empty()) return;
  scorer_.set_points(evaluation::uncovered_target_points(map, world_.truth, settings_.mapping.metrics));
  nbv::ViewEvaluator eval(index, world_.spec.camera, settings_.nbv.rays);
  const nbv::RaySetEntry& rays = nbv::ray_set(settings_.method.rays, "method.rays");
  const Pose* chosen = batch.views.empty() ? nullptr : &batch.views.front().T_world_camera;
  bool chosen_marked = false;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const nbv::ScoredView& v = pending_[i];
    CandidateRecord r;
    r.stop = stop;
    r.round = round;
    r.views_before = views_before;
    r.cluster = v.candidate.cluster;
    r.T_world_camera = v.candidate.T_world_camera;
    r.planner_gain = v.score.gain;
    if (chosen && !chosen_marked && r.T_world_camera.isApprox(*chosen, 1e-12)) r.chosen = chosen_marked = true;
    r.frustum = scorer_.in_frustum(r.T_world_camera);
    r.truth = scorer_.visible(r.T_world_camera);
    for (const auto& g : gains_)
      r.scores.push_back(eval.evaluate(v.candidate.T_world_camera, v.candidate.target, *g, rays, mix_seed(seed, i)).gain);
    records_.push_back(std::move(r));
  }
  pending_.clear();
}

std::string candidates_csv(const std::vector<CandidateRecord>& records) {
  std::string s = "stop,round,views_before,cluster,x,y,z,qw,qx,qy,qz,chosen,planner_gain,frustum,truth";
  for (const std::string& n : audit_score_names()) s += "," + n;
  s += "\n";
  char b[64];
  auto num = [&](double x) {
    std::snprintf(b, sizeof b, "%.17g", x);
    return std::string(b);
  };
  for (const CandidateRecord& r : records) {
    const Vec3 t = r.T_world_camera.translation();
    const Eigen::Quaterniond q(r.T_world_camera.linear());
    s += std::to_string(r.stop) + "," + std::to_string(r.round) + "," + std::to_string(r.views_before) + "," +
         std::to_string(r.cluster) + "," + num(t.x()) + "," + num(t.y()) + "," + num(t.z()) + "," + num(q.w()) + "," +
         num(q.x()) + "," + num(q.y()) + "," + num(q.z()) + "," + (r.chosen ? "1" : "0") + "," + num(r.planner_gain) +
         "," + std::to_string(r.frustum) + "," + std::to_string(r.truth);
    for (const double x : r.scores) s += "," + num(x);
    s += "\n";
  }
  return s;
}

std::vector<GainTruthRow> gain_truth(const std::vector<std::string>& files) {
  const std::vector<std::string> names = audit_score_names();
  std::vector<GainTruthRow> rows;
  rows.push_back({"planner", {}});
  for (const std::string& n : names) rows.push_back({n, {}});
  const std::size_t first_score = 15, columns = first_score + names.size();
  for (const std::string& file : files) {
    std::ifstream in(file);
    if (!in) throw InputError(file + ": cannot be read");
    std::string line;
    if (!std::getline(in, line) || line.rfind("stop,round,", 0) != 0) throw InputError(file + ": not a candidates.csv");
    // One round's columns: planner gain, each score, truth.
    std::vector<std::vector<double>> round(names.size() + 1);
    std::vector<double> truth;
    std::string key;
    auto flush = [&] {
      if (truth.size() >= 2)
        for (std::size_t k = 0; k < rows.size(); ++k) rows[k].agreement.add_round(round[k], truth);
      for (auto& r : round) r.clear();
      truth.clear();
    };
    long n = 1;
    while (std::getline(in, line)) {
      ++n;
      if (line.empty()) continue;
      std::vector<std::string> f;
      std::stringstream ss(line);
      std::string item;
      while (std::getline(ss, item, ',')) f.push_back(item);
      if (f.size() != columns) throw InputError(file + ":" + std::to_string(n) + ": expected " + std::to_string(columns) + " columns");
      try {
        const std::string k = f[0] + "," + f[1];
        if (k != key) {
          flush();
          key = k;
        }
        round[0].push_back(std::stod(f[12]));
        for (std::size_t j = 0; j < names.size(); ++j) round[j + 1].push_back(std::stod(f[first_score + j]));
        truth.push_back(std::stod(f[14]));
      } catch (const std::logic_error&) {
        throw InputError(file + ":" + std::to_string(n) + ": not a number");
      }
    }
    flush();
  }
  return rows;
}

std::string gain_truth_csv(const std::vector<GainTruthRow>& rows) {
  std::string s = "score,rounds,spearman,top1,top5,mean_oracle_rank,truth_share\n";
  char b[256];
  for (const GainTruthRow& r : rows) {
    const evaluation::RankAgreement& a = r.agreement;
    std::snprintf(b, sizeof b, "%s,%zu,%.4f,%.4f,%.4f,%.3f,%.4f\n", r.score.c_str(), a.rounds, a.mean_spearman(),
                  a.top1_rate(), a.top5_rate(), a.mean_rank(), a.mean_truth_share());
    s += b;
  }
  return s;
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
  OraclePlanner(const nbv::ViewPlannerSettings& s, bool any)
      : ViewPlanner(s.params.views), settings_(s), any_(any), done_(s.params.views), failed_(s.params.views) {
    context_ = dynamic_cast<const MissionContext*>(s.context.get());
    if (!context_ || !context_->world || !context_->sim)
      throw InputError(std::string("method ") + name() +
                       " reads the ground truth: it runs only in a mission (canopy mission, run, experiment)");
  }

  std::string name() const override { return any_ ? "oracle_any" : "oracle"; }

  void taken(const Pose& T) override {
    ViewPlanner::taken(T);
    failed_.taken(T);
  }
  void begin_stop() override { failed_.begin_stop(); }

  nbv::ViewBatch next(const nbv::ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    const OracleParams& op = context_->oracle;
    if (!scorer_)
      scorer_ = std::make_unique<TruthViewScorer>(*context_->sim, settings_.intrinsics, op.render_downsample,
                                                  op.depth_tolerance_m);
    failed_.next_batch();
    nbv::ViewBatch batch;
    batch.order = nbv::BatchOrder::kUtility;
    {
      ScopedPhase phase(batch.times, "truth");
      scorer_->set_points(evaluation::uncovered_target_points(*req.map, context_->world->truth, context_->metrics));
    }
    std::vector<TruthView> views = any_ ? dense_views(req, &batch) : ours_views(req, &batch);
    if (views.empty()) {
      batch.finished = true;
      if (batch.reason.empty()) batch.reason = "no candidate left";
      return batch;
    }
    // The best views by the truth (branch and bound); oracle_any's reach test runs only on
    // the views it renders.
    std::vector<TruthScore> best;
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
      best = best_truth_views(*scorer_, &poses, std::size_t(op.max_views), accept);
      for (std::size_t i = 0; i < views.size(); ++i) views[i].bound = scorer_->in_frustum(poses[i]);
    }
    for (const TruthScore& t : best)
      batch.views.push_back(nbv::planned_view(views[t.view].candidate, double(t.score), any_ ? "oracle_any" : "oracle"));
    for (const nbv::PlannedView& v : batch.views) failed_.offered(v.T_world_camera);
    if (!any_) mark_done(views);
    batch.finished = batch.views.empty();
    if (batch.finished) batch.reason = "no candidate sees an uncovered fruit point (ground truth)";
    return batch;
  }

 private:
  // Ours' candidates: clusters of the map (minus done ones), the sphere around each, taken
  // views and the reach test exactly as ours applies them.
  std::vector<TruthView> ours_views(const nbv::ViewRequest& req, nbv::ViewBatch* batch) {
    std::vector<TruthView> out;
    clusters_.clear();
    {
      ScopedPhase phase(batch->times, "clustering");
      req.index->refresh(*req.map);
      for (nbv::Cluster& c : nbv::find_clusters(*req.map, settings_.params.cluster, &req.region))
        if (!done_.contains(c.centroid)) clusters_.push_back(c);
    }
    batch->clusters = clusters_.size();
    if (clusters_.empty()) {
      batch->reason = done_.size() ? "every cluster in reach is done" : "no fruit clusters in reach";
      return out;
    }
    ScopedPhase phase(batch->times, "filtering");
    for (std::size_t c = 0; c < clusters_.size(); ++c)
      for (nbv::Candidate& cand : nbv::sample_candidates(clusters_[c].centroid, int(c), settings_.params.candidates)) {
        if (taken_.contains(cand.T_world_camera) || (req.reach && !req.reach(&cand)) ||
            taken_.contains(cand.T_world_camera) || failed_.contains(cand.T_world_camera)) {
          ++batch->filtered;
          continue;
        }
        out.push_back({cand, 0, 0});
      }
    batch->candidates = out.size();
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
    const OracleParams& op = context_->oracle;
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
  nbv::DoneClusters done_;
  nbv::FailedViews failed_{nbv::ViewRules{}};
  std::vector<nbv::Cluster> clusters_;
  std::unique_ptr<TruthViewScorer> scorer_;
};

}  // namespace

void register_oracle_planners() {
  static std::once_flag once;
  std::call_once(once, [] {
    nbv::register_view_planner({"oracle",
                                "ORACLE, READS THE GROUND TRUTH: ours' candidates, workspace filter and reach test, each "
                                "scored by the uncovered true fruit points it sees (a bound, not a method)",
                                [](const nbv::ViewPlannerSettings& s) {
                                  return std::unique_ptr<nbv::ViewPlanner>(new OraclePlanner(s, false));
                                },
                                true});
    nbv::register_view_planner({"oracle_any",
                                "ORACLE, READS THE GROUND TRUTH: a dense set of reachable views around every fruit of the "
                                "stop, scored by the uncovered true fruit points they see (a bound, not a method)",
                                [](const nbv::ViewPlannerSettings& s) {
                                  return std::unique_ptr<nbv::ViewPlanner>(new OraclePlanner(s, true));
                                },
                                true});
  });
}

}  // namespace canopy::mission
