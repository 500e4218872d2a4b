#include "canopy/datasets/frame_io.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/png_io.h"
#include "canopy/common/value_text.h"

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

EncodedFrame encode_frame(const LabelledFrame& frame, const SemanticClasses& classes, InstanceEncoding instances) {
  const int W = frame.rgb.width, H = frame.rgb.height;
  EncodedFrame e;
  e.depth_mm = Image<std::uint16_t>(W, H, 0);
  e.labels = Image<Rgb8>(W, H);
  if (instances == InstanceEncoding::kColors) e.instance_colors = Image<Rgb8>(W, H);
  else e.instance_ids = Image<std::uint16_t>(W, H, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = frame.depth_m.at(x, y);
      if (z > 0.f && std::isfinite(z))
        e.depth_mm.at(x, y) = static_cast<std::uint16_t>(std::min(65535.0, std::round(1000.0 * z)));
      e.labels.at(x, y) = classes.color(frame.class_id.at(x, y));
      const std::int32_t id = frame.instance.at(x, y);
      if (instances == InstanceEncoding::kColors) {
        e.instance_colors.at(x, y) = instance_color(id);
      } else if (id != kNoInstance) {
        if (id < 0 || id >= 65535)
          throw std::invalid_argument("instance id " + std::to_string(id) + " does not fit 16 bits");
        e.instance_ids.at(x, y) = static_cast<std::uint16_t>(id + 1);
      }
    }
  return e;
}

void put_frame_intrinsics(nlohmann::json* frame_json, const CameraIntrinsics& K) {
  nlohmann::json k = params_to_json(K);
  (*frame_json)["valid_range_m"] = {k["min_range_m"], k["max_range_m"]};
  (*frame_json)["depth_noise_k"] = k["depth_noise_k"];
  for (const char* key : {"min_range_m", "max_range_m", "depth_noise_k"}) k.erase(key);
  (*frame_json)["intrinsics"] = k;
}

void write_frame(const std::string& prefix, const LabelledFrame& frame, const SemanticClasses& classes) {
  const EncodedFrame e = encode_frame(frame, classes, InstanceEncoding::kColors);
  write_png(prefix + "rgb.png", frame.rgb);
  write_png_gray16(prefix + "depth.png", e.depth_mm);
  write_png(prefix + "labels.png", e.labels);
  write_png(prefix + "instances.png", e.instance_colors);
  nlohmann::json j;
  put_frame_intrinsics(&j, frame.intrinsics);
  j["T_world_camera"] = pose_to_json(frame.T_world_camera);
  j["camera_frame"] = "x right, y down, z forward; pixel (i, j) centre at (i + 0.5, j + 0.5)";
  j["depth_png"] = "uint16 millimetres of planar z-depth, 0 = invalid";
  j["classes"] = classes.names;
  write_json_atomic(prefix + "frame.json", j);
}

}  // namespace canopy::datasets
