#pragma once
// The truth scorer: how many not yet covered target-fruit surface points a camera pose sees.
// READS THE GROUND TRUTH (the points it is given, from evaluation::uncovered_target_points, and
// a depth render of the true scene). It bounds what a planner can reach and measures how well
// the planners' gains rank views (the oracle planners and the candidate audit of mission/oracle/).
//
// A point is seen when it lies in the camera's valid depth range and image, and its depth
// passes a test against the depth the renderer draws at its pixel (robot hidden). The render
// may be coarser than the camera's (truth_render_intrinsics); a test shows the coarse one
// agrees with the full one. The renderer comes in as a function, so this module stays free of
// the simulator (mission/oracle/oracle_planners.h makes one from sim::Renderer).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/image.h"
#include "canopy/common/types.h"
#include "canopy/evaluation/map_metrics.h"

namespace canopy::evaluation {

/// Draws the true scene's planar depth [m] (0 = nothing) from a camera pose, at the scorer's
/// render intrinsics.
using TruthDepthRender = std::function<Image<float>(const Pose& T_world_camera)>;

/// The camera divided by `downsample` on each side, without depth noise: the truth render's
/// intrinsics.
CameraIntrinsics truth_render_intrinsics(const CameraIntrinsics& camera, int downsample);

/// Counts the given truth points a camera pose sees.
class TruthViewScorer {
 public:
  /// `render` draws at `render_intrinsics`; a point passes the depth test within
  /// `depth_tolerance_m` plus 1.5 render pixels.
  TruthViewScorer(const CameraIntrinsics& render_intrinsics, double depth_tolerance_m, TruthDepthRender render);

  /// The points still to be seen (e.g. uncovered_target_points of the current map).
  void set_points(std::vector<UncoveredPoint> points);
  /// The points set last.
  const std::vector<UncoveredPoint>& points() const { return points_; }

  /// Renders each pose once while the scene stays still: `universe` holds every point
  /// set_points() will be given (UncoveredPoint::index into it, e.g. target_surface_points).
  /// visible() then keeps, per pose (bit for bit), which universe points the pose sees and
  /// later only counts those among the points set; the counts equal rendering again.
  /// Call forget_views() when the scene may have changed.
  void cache_views(std::vector<Vec3> universe);
  /// Drops the views kept by cache_views (the universe stays).
  void forget_views() { views_.clear(); }

  /// Points inside the view's frustum and valid depth range (no occlusion): an upper bound of
  /// visible(), without rendering.
  std::size_t in_frustum(const Pose& T_world_camera) const;
  /// Points the view sees: in the frustum and not behind the rendered true surface.
  std::size_t visible(const Pose& T_world_camera);

  /// The intrinsics the truth is rendered at.
  const CameraIntrinsics& render_intrinsics() const { return intrinsics_; }
  /// Renders made so far.
  std::size_t renders() const { return renders_; }
  /// visible() calls answered from the views kept (cache_views).
  std::size_t reused() const { return reused_; }

 private:
  // Whether point p (camera frame c) passes the depth test against `depth`.
  bool sees(const Image<float>& depth, const Vec3& c, double u, double v) const;

  // Consecutive points in a ball: a pose's frustum test runs once per ball and point by point
  // only for balls that straddle its boundary (a margin keeps the answer the per-point one).
  struct Ball {
    Vec3 center;
    double radius = 0.0;
    std::size_t begin = 0, end = 0;
  };
  enum class Side { kOutside, kInside, kStraddles };
  static std::vector<Ball> make_balls(const std::vector<Vec3>& points);
  Side side(const Pose& T_inv, const Ball& b) const;

  CameraIntrinsics intrinsics_;
  double tolerance_m_;
  TruthDepthRender render_;
  std::vector<UncoveredPoint> points_;
  std::vector<Ball> point_balls_, universe_balls_;
  std::size_t renders_ = 0, reused_ = 0;
  // cache_views: the universe, which of its points are set now, and per pose (its 3x4 matrix)
  // the universe points it sees, ascending.
  std::vector<Vec3> universe_;
  std::vector<std::uint8_t> current_;
  std::map<std::array<double, 12>, std::vector<std::uint32_t>> views_;
};

/// A view scored by the truth.
struct TruthScore {
  std::size_t view = 0;    ///< Index into the views given.
  std::size_t bound = 0;   ///< Uncovered points in its frustum.
  std::size_t score = 0;   ///< Uncovered points it sees.
};

/// The `keep` views of `views` that see the most uncovered points (score > 0), best first
/// (ties: the earlier view), by branch and bound: views are rendered in the order of their
/// frustum bound until the bound cannot beat the keep-th best score, so the answer equals
/// rendering every view. `accept(i, &pose)`, when given, is asked just before view i is
/// rendered; it may move the pose (a reach test) or refuse the view. `bounds`, when given,
/// receives every view's frustum bound at its final pose (in_frustum(views[i]) afterwards).
std::vector<TruthScore> best_truth_views(TruthViewScorer& scorer, std::vector<Pose>* views, std::size_t keep,
                                         const std::function<bool(std::size_t, Pose*)>& accept = nullptr,
                                         std::vector<std::size_t>* bounds = nullptr);

}  // namespace canopy::evaluation
