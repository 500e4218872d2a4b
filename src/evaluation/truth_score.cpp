// The truth scorer (evaluation/truth_score.h). READS THE GROUND TRUTH.

#include "canopy/evaluation/truth_score.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "canopy/common/error.h"

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

void TruthViewScorer::set_points(std::vector<UncoveredPoint> points) {
  points_ = std::move(points);
  std::vector<Vec3> positions(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) positions[i] = points_[i].position;
  point_balls_ = make_balls(positions);
  if (universe_.empty()) return;
  std::fill(current_.begin(), current_.end(), std::uint8_t(0));
  for (const UncoveredPoint& p : points_) {
    CANOPY_CHECK(p.index < universe_.size() && universe_[p.index] == p.position,
                 "truth scorer: a point is not the universe's point of its index");
    current_[p.index] = 1;
  }
}

void TruthViewScorer::cache_views(std::vector<Vec3> universe) {
  CANOPY_CHECK(universe.size() < (std::size_t(1) << 32), "truth scorer: universe too large");
  universe_ = std::move(universe);
  universe_balls_ = make_balls(universe_);
  current_.assign(universe_.size(), 0);
  views_.clear();
  std::vector<UncoveredPoint> points = std::move(points_);
  set_points(std::move(points));
}

namespace {

// Point p in the camera frame (*c) and its pixel (*u, *v) when it lies in the valid depth range
// and the image of `K`.
bool in_view(const CameraIntrinsics& K, const Pose& T_inv, const Vec3& p, Vec3* c, double* u, double* v) {
  *c = T_inv * p;
  if (c->z() < K.min_range_m || c->z() > K.max_range_m) return false;
  return K.project(*c, u, v) && *u >= 0.0 && *v >= 0.0 && *u < K.width_px && *v < K.height_px;
}

}  // namespace

// Balls of at most 64 consecutive points: the points' mean and the largest distance to it.
std::vector<TruthViewScorer::Ball> TruthViewScorer::make_balls(const std::vector<Vec3>& points) {
  constexpr std::size_t kBall = 64;
  std::vector<Ball> out;
  for (std::size_t b = 0; b < points.size(); b += kBall) {
    Ball ball;
    ball.begin = b;
    ball.end = std::min(points.size(), b + kBall);
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = ball.begin; i < ball.end; ++i) sum += points[i];
    ball.center = sum / double(ball.end - ball.begin);
    for (std::size_t i = ball.begin; i < ball.end; ++i)
      ball.radius = std::max(ball.radius, (points[i] - ball.center).norm());
    out.push_back(ball);
  }
  return out;
}

// in_view() of every point of the ball, when one answer holds for all: the ball (grown by a
// margin far above the rounding of in_view's arithmetic) lies wholly outside one of the
// frustum's six half-spaces, or wholly inside all of them.
TruthViewScorer::Side TruthViewScorer::side(const Pose& T_inv, const Ball& b) const {
  const CameraIntrinsics& K = intrinsics_;
  if (!(K.min_range_m > 0.0)) return Side::kStraddles;  // in_view's z > 0 test stands on min_range
  constexpr double kMargin = 1e-6;  // [m]
  const double r = b.radius + kMargin;
  const Vec3 c = T_inv * b.center;
  // Signed distances to the planes u = 0, u = W, v = 0, v = H (positive inside) and the range.
  const double W = K.width_px, H = K.height_px;
  const double d[6] = {
      (K.fx_px * c.x() + K.cx_px * c.z()) / std::hypot(K.fx_px, K.cx_px),
      (-K.fx_px * c.x() + (W - K.cx_px) * c.z()) / std::hypot(K.fx_px, W - K.cx_px),
      (K.fy_px * c.y() + K.cy_px * c.z()) / std::hypot(K.fy_px, K.cy_px),
      (-K.fy_px * c.y() + (H - K.cy_px) * c.z()) / std::hypot(K.fy_px, H - K.cy_px),
      c.z() - K.min_range_m,
      K.max_range_m - c.z(),
  };
  bool inside = true;
  for (const double x : d) {
    if (x < -r) return Side::kOutside;
    if (!(x > r)) inside = false;
  }
  return inside ? Side::kInside : Side::kStraddles;
}

std::size_t TruthViewScorer::in_frustum(const Pose& T) const {
  const Pose T_inv = T.inverse();
  std::size_t n = 0;
  Vec3 c;
  double u = 0, v = 0;
  for (const Ball& b : point_balls_) {
    const Side s = side(T_inv, b);
    if (s == Side::kOutside) continue;
    if (s == Side::kInside) {
      n += b.end - b.begin;
      continue;
    }
    for (std::size_t i = b.begin; i < b.end; ++i) n += in_view(intrinsics_, T_inv, points_[i].position, &c, &u, &v);
  }
  return n;
}

bool TruthViewScorer::sees(const Image<float>& depth, const Vec3& c, double u, double v) const {
  const float d = depth.at(int(u), int(v));
  if (!(d > 0.f)) return false;
  // A pixel spans z / fx metres; a slanted surface changes depth by about that much across it.
  const double tol = tolerance_m_ + 1.5 * c.z() / intrinsics_.fx_px;
  return c.z() <= double(d) + tol;
}

std::size_t TruthViewScorer::visible(const Pose& T) {
  if (in_frustum(T) == 0) return 0;
  std::array<double, 12> key{};
  if (!universe_.empty()) {
    for (int i = 0; i < 12; ++i) key[std::size_t(i)] = T.matrix()(i % 3, i / 3);
    const auto it = views_.find(key);
    if (it != views_.end()) {
      ++reused_;
      std::size_t n = 0;
      for (const std::uint32_t i : it->second) n += current_[i];
      return n;
    }
  }
  const Image<float> depth = render_(T);
  ++renders_;
  const Pose T_inv = T.inverse();
  Vec3 c;
  double u = 0, v = 0;
  if (!universe_.empty()) {  // every universe point, kept for the next rounds
    std::vector<std::uint32_t> seen;
    std::size_t n = 0;
    for (const Ball& b : universe_balls_) {
      if (side(T_inv, b) == Side::kOutside) continue;
      for (std::size_t i = b.begin; i < b.end; ++i)
        if (in_view(intrinsics_, T_inv, universe_[i], &c, &u, &v) && sees(depth, c, u, v)) {
          seen.push_back(std::uint32_t(i));
          n += current_[i];
        }
    }
    views_.emplace(key, std::move(seen));
    return n;
  }
  std::size_t n = 0;
  for (const Ball& b : point_balls_) {
    if (side(T_inv, b) == Side::kOutside) continue;
    for (std::size_t i = b.begin; i < b.end; ++i)
      if (in_view(intrinsics_, T_inv, points_[i].position, &c, &u, &v) && sees(depth, c, u, v)) ++n;
  }
  return n;
}

std::vector<TruthScore> best_truth_views(TruthViewScorer& scorer, std::vector<Pose>* views, std::size_t keep,
                                         const std::function<bool(std::size_t, Pose*)>& accept,
                                         std::vector<std::size_t>* bounds) {
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
      const bool accepted = accept(t.view, &pose);
      all[t.view].bound = scorer.in_frustum(pose);  // it may have moved the pose
      if (!accepted) continue;
      t.bound = all[t.view].bound;
    }
    t.score = scorer.visible(pose);
    if (t.score == 0) continue;
    best.insert(std::upper_bound(best.begin(), best.end(), t, better), t);
    if (best.size() > keep) best.pop_back();
  }
  if (bounds) {
    bounds->resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) (*bounds)[i] = all[i].bound;
  }
  return best;
}

}  // namespace canopy::evaluation
