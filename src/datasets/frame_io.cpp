#include "canopy/datasets/frame_io.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/io.h"

namespace canopy::datasets {

Rgb8 instance_color(std::int32_t id) {
  if (id == kNoInstance) return {0, 0, 0};
  // Golden-ratio hue walk: neighbouring ids get well separated colours.
  const double h = std::fmod(0.13 + 0.618033988749895 * id, 1.0) * 6.0;
  const double f = h - std::floor(h);
  const auto c = [](double v) { return static_cast<std::uint8_t>(std::lround(55 + 200 * v)); };
  switch (static_cast<int>(h)) {
    case 0: return {c(1), c(f), c(0)};
    case 1: return {c(1 - f), c(1), c(0)};
    case 2: return {c(0), c(1), c(f)};
    case 3: return {c(0), c(1 - f), c(1)};
    case 4: return {c(f), c(0), c(1)};
    default: return {c(1), c(0), c(1 - f)};
  }
}

void write_frame(const std::string& prefix, const LabelledFrame& frame, const SemanticClasses& classes) {
  const int W = frame.rgb.width, H = frame.rgb.height;
  write_png(prefix + "rgb.png", frame.rgb);
  Image<std::uint16_t> depth_mm(W, H, 0);
  Image<Rgb8> labels(W, H), instances(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = frame.depth_m.at(x, y);
      if (z > 0.f && std::isfinite(z))
        depth_mm.at(x, y) = static_cast<std::uint16_t>(std::min(65535.0, std::round(1000.0 * z)));
      labels.at(x, y) = classes.color(frame.class_id.at(x, y));
      instances.at(x, y) = instance_color(frame.instance.at(x, y));
    }
  write_png_gray16(prefix + "depth.png", depth_mm);
  write_png(prefix + "labels.png", labels);
  write_png(prefix + "instances.png", instances);
  const CameraIntrinsics& K = frame.intrinsics;
  nlohmann::json j;
  j["intrinsics"] = {{"width_px", K.width_px}, {"height_px", K.height_px}, {"fx_px", K.fx_px}, {"fy_px", K.fy_px},
                     {"cx_px", K.cx_px},       {"cy_px", K.cy_px}};
  j["valid_range_m"] = {K.min_range_m, K.max_range_m};
  j["depth_noise_k"] = K.depth_noise_k;
  j["T_world_camera"] = pose_to_json(frame.T_world_camera);
  j["camera_frame"] = "x right, y down, z forward; pixel (i, j) centre at (i + 0.5, j + 0.5)";
  j["depth_png"] = "uint16 millimetres of planar z-depth, 0 = invalid";
  j["classes"] = classes.names;
  write_json_atomic(prefix + "frame.json", j);
}

}  // namespace canopy::datasets
