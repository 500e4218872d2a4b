// The truth scorer (evaluation/truth_score.h). READS THE GROUND TRUTH.

#include "canopy/evaluation/truth_score.h"

#include <algorithm>
#include <utility>

namespace canopy::evaluation {

CameraIntrinsics truth_render_intrinsics(const CameraIntrinsics& K, int downsample) {
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

TruthViewScorer::TruthViewScorer(const CameraIntrinsics& render_intrinsics, double depth_tolerance_m,
                                 TruthDepthRender render)
    : intrinsics_(render_intrinsics), tolerance_m_(depth_tolerance_m), render_(std::move(render)) {}

void TruthViewScorer::set_points(std::vector<UncoveredPoint> points) { points_ = std::move(points); }

namespace {

// Point p in the camera frame (*c) and its pixel (*u, *v) when it lies in the valid depth range
// and the image of `K`.
bool in_view(const CameraIntrinsics& K, const Pose& T_inv, const Vec3& p, Vec3* c, double* u, double* v) {
  *c = T_inv * p;
  if (c->z() < K.min_range_m || c->z() > K.max_range_m) return false;
  return K.project(*c, u, v) && *u >= 0.0 && *v >= 0.0 && *u < K.width_px && *v < K.height_px;
}

}  // namespace

std::size_t TruthViewScorer::in_frustum(const Pose& T) const {
  const Pose T_inv = T.inverse();
  std::size_t n = 0;
  Vec3 c;
  double u = 0, v = 0;
  for (const UncoveredPoint& p : points_) n += in_view(intrinsics_, T_inv, p.position, &c, &u, &v);
  return n;
}

std::size_t TruthViewScorer::visible(const Pose& T) {
  if (in_frustum(T) == 0) return 0;
  const Image<float> depth = render_(T);
  ++renders_;
  const Pose T_inv = T.inverse();
  std::size_t n = 0;
  Vec3 c;
  double u = 0, v = 0;
  for (const UncoveredPoint& p : points_) {
    if (!in_view(intrinsics_, T_inv, p.position, &c, &u, &v)) continue;
    const float d = depth.at(int(u), int(v));
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

}  // namespace canopy::evaluation
