#pragma once
// Writing a LabelledFrame as image files a person can open. encode_frame() is the one frame
// encoder: `canopy render`'s frame folders (write_frame) and the nerfstudio dataset export
// (mission/dataset_export) both turn a frame into its images through it.

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
#include "canopy/common/frame.h"

namespace canopy::datasets {

/// Colour of fruit instance `id` in instance images (black for kNoInstance).
Rgb8 instance_color(std::int32_t id);

/// How an instance image holds fruit instance ids.
enum class InstanceEncoding {
  kColors,  ///< 8-bit RGB, instance_color(id): for people (frame folders).
  kIds16,   ///< 16-bit id + 1, 0 = no fruit: for programs (datasets).
};

/// A frame's images as written to disk (the instance image in the encoding asked for).
struct EncodedFrame {
  Image<std::uint16_t> depth_mm;      ///< Planar z-depth in millimetres (rounded), 0 = invalid.
  Image<Rgb8> labels;                 ///< Class colours (SemanticClasses::color).
  Image<Rgb8> instance_colors;        ///< kColors only.
  Image<std::uint16_t> instance_ids;  ///< kIds16 only.
};

/// Encodes depth, labels and instances of `frame` (all of the RGB image's size); kIds16 throws
/// std::invalid_argument for an id that does not fit 16 bits.
EncodedFrame encode_frame(const LabelledFrame& frame, const SemanticClasses& classes, InstanceEncoding instances);

/// frame.json's intrinsics: the pinhole keys under "intrinsics", the depth range as
/// "valid_range_m" [min, max] and "depth_noise_k" beside them (the layout frame folders have
/// always had; FrameSequence reads it back through CameraIntrinsics::visit).
void put_frame_intrinsics(nlohmann::json* frame_json, const CameraIntrinsics& K);

/// Writes `<prefix>rgb.png`, `<prefix>depth.png` (16-bit millimetres, 0 = invalid),
/// `<prefix>labels.png` (class colours), `<prefix>instances.png` and `<prefix>frame.json`
/// (intrinsics, T_world_camera, valid range, class names), each atomically.
void write_frame(const std::string& prefix, const LabelledFrame& frame, const SemanticClasses& classes);

}  // namespace canopy::datasets
