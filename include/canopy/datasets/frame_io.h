#pragma once
// Writing a LabelledFrame as image files a person can open.

#include <string>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"

namespace canopy::datasets {

/// Colour of fruit instance `id` in instance images (black for kNoInstance).
Rgb8 instance_color(std::int32_t id);

/// Writes `<prefix>rgb.png`, `<prefix>depth.png` (16-bit millimetres, 0 = invalid),
/// `<prefix>labels.png` (class colours), `<prefix>instances.png` and `<prefix>frame.json`
/// (intrinsics, T_world_camera, valid range, class names), each atomically.
void write_frame(const std::string& prefix, const LabelledFrame& frame, const SemanticClasses& classes);

}  // namespace canopy::datasets
