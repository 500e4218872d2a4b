#include "canopy/perception/semantic_extractor.h"

#include <algorithm>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/perception/segmentation_noise.h"

namespace canopy::perception {

SemanticExtractor::SemanticExtractor(const ExtractorParams& params, const SemanticClasses& classes)
    : params_(params), classes_(classes), rng_(params.seed) {}

Image<std::uint8_t> SemanticExtractor::label(const LabelledFrame& frame, ExtractStats* stats) {
  Image<std::uint8_t> labels;
  if (params_.source == LabelSource::kTruth) {
    if (frame.class_id.empty()) throw InputError("semantic extractor: frame has no true labels (--seg truth)");
    labels = frame.class_id;
  } else {
    if (frame.rgb.empty()) throw InputError("semantic extractor: frame has no RGB image (--seg color)");
    labels = segment_by_color(frame.rgb, params_.color, classes_);
  }
  // Masks split by fruit instance only when labels are the truth (colour segmentation
  // cannot tell touching fruits apart).
  static const Image<std::int32_t> kNone;
  const Image<std::int32_t>& instance = params_.source == LabelSource::kTruth ? frame.instance : kNone;
  const MaskNoiseStats n =
      apply_segmentation_noise(params_.noise, labels, instance, classes_.size(), params_.p_gt, rng_);
  stats->masks += n.masks;
  stats->masks_flipped += n.flipped;
  return labels;
}

LabelledCloud SemanticExtractor::extract(const LabelledFrame& frame, Image<std::uint8_t>* labels_out) {
  ExtractStats stats;
  Image<std::uint8_t> labels = label(frame, &stats);
  LabelledCloud cloud;
  const double missing = params_.missing_depth == MissingDepth::kCarve ? params_.missing_depth_m : 0.0;
  if (params_.depth_noise_k > 0.0) {
    Image<float> depth = frame.depth_m;
    for (float& z : depth.data) {
      if (!(std::isfinite(z) && z > 0.f)) continue;
      const double g = rng_.normal();
      z = static_cast<float>(z + g * params_.depth_noise_k * double(z) * double(z));
    }
    cloud = depth_to_cloud(frame.intrinsics, frame.T_world_camera, depth, labels, classes_.size(), missing);
  } else {
    cloud = depth_to_cloud(frame.intrinsics, frame.T_world_camera, frame.depth_m, labels, classes_.size(), missing);
  }
  cloud.stats.masks = stats.masks;
  cloud.stats.masks_flipped = stats.masks_flipped;
  const auto target = static_cast<std::uint8_t>(classes_.target_index());
  cloud.stats.target_points = static_cast<std::size_t>(std::count(cloud.labels.begin(), cloud.labels.end(), target));
  cloud.stats.true_target_pixels =
      static_cast<std::size_t>(std::count(frame.class_id.data.begin(), frame.class_id.data.end(), target));
  if (labels_out) *labels_out = std::move(labels);
  return cloud;
}

LabelledCloud depth_to_cloud(const CameraIntrinsics& K, const Pose& T_world_camera, const Image<float>& depth_m,
                             const Image<std::uint8_t>& labels, int num_classes, double missing_depth_m) {
  if (depth_m.width != labels.width || depth_m.height != labels.height)
    throw InputError("semantic extractor: depth image is " + std::to_string(depth_m.width) + "x" +
                     std::to_string(depth_m.height) + " but the label image is " + std::to_string(labels.width) +
                     "x" + std::to_string(labels.height));
  LabelledCloud cloud;
  cloud.origin_world = T_world_camera.translation();
  cloud.R_world_camera = T_world_camera.linear();
  cloud.points_world.reserve(depth_m.data.size());
  cloud.labels.reserve(depth_m.data.size());
  const Eigen::Matrix3f R = T_world_camera.linear().cast<float>();
  const Vec3f t = T_world_camera.translation().cast<float>();
  ExtractStats& s = cloud.stats;
  for (int j = 0; j < depth_m.height; ++j) {
    for (int i = 0; i < depth_m.width; ++i) {
      ++s.pixels;
      float z = depth_m.at(i, j);
      std::uint8_t c = labels.at(i, j);
      if (!std::isfinite(z) || z <= 0.f) {
        if (!(missing_depth_m > 0.0) || z < 0.f) {  // negative depth is wrong data, not "no return"
          ++s.bad_depth;
          continue;
        }
        // No return: a point far along the pixel's ray, whose ray carves free space.
        ++s.missing_depth;
        z = static_cast<float>(missing_depth_m);
        c = 0;
      } else if (z < K.min_range_m || z > K.max_range_m) {
        ++s.out_of_range;
        continue;
      }
      if (c >= num_classes) {
        ++s.bad_label;
        continue;
      }
      const Vec3f p_camera(float((i + 0.5 - K.cx_px) / K.fx_px) * z, float((j + 0.5 - K.cy_px) / K.fy_px) * z, z);
      cloud.points_world.push_back(R * p_camera + t);
      cloud.labels.push_back(c);
    }
  }
  s.points = cloud.points_world.size();
  return cloud;
}

std::string to_string(LabelSource s) { return enum_name(kLabelSourceNames, s); }

LabelSource label_source_from_string(const std::string& s, const std::string& where) {
  return enum_from_name(kLabelSourceNames, s, where, "label source");
}

}  // namespace canopy::perception
