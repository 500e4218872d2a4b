#pragma once
// One labelled RGB-D observation: what the renderer (or a real camera plus a segmenter)
// hands to perception and mapping.

#include <cstdint>

#include "canopy/common/camera.h"
#include "canopy/common/image.h"
#include "canopy/common/types.h"

namespace canopy {

/// Instance id of pixels that belong to no fruit.
constexpr std::int32_t kNoInstance = -1;

/// A rendered or captured frame with its intrinsics and camera pose.
struct LabelledFrame {
  CameraIntrinsics intrinsics;
  Pose T_world_camera = Pose::Identity();
  Image<Rgb8> rgb;
  Image<float> depth_m;            ///< Planar z-depth [m]; 0 = invalid (outside the valid range).
  Image<std::uint8_t> class_id;    ///< Semantic class index (into SemanticClasses::names).
  Image<std::int32_t> instance;    ///< Fruit instance id, kNoInstance elsewhere.
};

}  // namespace canopy
