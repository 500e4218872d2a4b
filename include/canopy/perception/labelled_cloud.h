#pragma once
// A labelled point cloud in the world frame: what the semantic extractor produces and the
// semantic map consumes.

#include <cstdint>
#include <vector>

#include "canopy/common/types.h"

namespace canopy::perception {

/// Counters of pixels that did not become points, and of segmentation noise.
struct ExtractStats {
  std::size_t pixels = 0;             ///< Pixels looked at.
  std::size_t points = 0;             ///< Points produced.
  std::size_t bad_depth = 0;          ///< NaN, inf, zero or negative depth (skipped).
  std::size_t missing_depth = 0;      ///< No return, given the missing depth (carved, not skipped).
  std::size_t out_of_range = 0;       ///< Depth below min_range_m or above max_range_m (skipped).
  std::size_t bad_label = 0;          ///< Label outside the class list (skipped).
  std::size_t masks = 0;              ///< Non-background masks seen by the noise model.
  std::size_t masks_flipped = 0;      ///< Masks given a wrong class.
  std::size_t target_points = 0;      ///< Points labelled the target class (SemanticExtractor::extract).
  std::size_t true_target_pixels = 0; ///< Pixels of the target class in the frame's true labels (0 without them).
};

/// Points in the world frame with one class label each, and the sensor origin.
struct LabelledCloud {
  Vec3 origin_world = Vec3::Zero();   ///< Camera position (where every ray starts).
  /// Camera orientation (world from camera): the axes of the per-endpoint voxel filter's grid.
  Eigen::Matrix3d R_world_camera = Eigen::Matrix3d::Identity();
  std::vector<Vec3f> points_world;    ///< Endpoints in the world frame [m].
  std::vector<std::uint8_t> labels;   ///< Class index per point (into SemanticClasses).
  ExtractStats stats;

  std::size_t size() const { return points_world.size(); }
  void clear() {
    points_world.clear();
    labels.clear();
    stats = {};
  }
};

}  // namespace canopy::perception
