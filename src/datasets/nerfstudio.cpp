// nerfstudio datasets of what the robot saw, with held-out views (dataset_export.h).

#include "canopy/datasets/nerfstudio.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/datasets/frame_io.h"

namespace canopy::datasets {

Eigen::Matrix4d opengl_camera_to_world(const Pose& T_world_camera) {
  Eigen::Matrix4d M = T_world_camera.matrix();
  M.col(1) = -M.col(1);  // y down -> y up
  M.col(2) = -M.col(2);  // z forward -> z back
  return M;
}

namespace {

bool little_endian() {
  const std::uint32_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

std::string frame_name(const std::string& set, std::size_t i) {
  char b[32];
  c_snprintf(b, sizeof b, "%s_%04zu", set.c_str(), i);
  return b;
}

}  // namespace

void write_npy_float32(const std::string& path, const Image<float>& image) {
  if (!little_endian()) throw std::runtime_error("write_npy_float32: needs a little-endian machine");
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(image.height) + ", " +
                       std::to_string(image.width) + "), }";
  // Magic (6) + version (2) + length (2) + header + '\n', padded to a multiple of 64.
  const std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  const std::size_t bytes = image.data.size() * sizeof(float);
  const std::size_t at = out.size();
  out.resize(at + bytes);
  if (bytes) std::memcpy(&out[at], image.data.data(), bytes);
  write_file_atomic(path, out);
}

Image<float> read_npy_float32(const std::string& path) {
  const std::string s = read_file(path);
  if (s.size() < 10 || s.compare(0, 6, "\x93NUMPY") != 0 || s[6] != 1)
    throw InputError(path + ": not a NumPy .npy file of version 1");
  const std::size_t len = static_cast<unsigned char>(s[8]) | (std::size_t(static_cast<unsigned char>(s[9])) << 8);
  if (s.size() < 10 + len) throw InputError(path + ": truncated .npy header");
  const std::string header = s.substr(10, len);
  if (header.find("'descr': '<f4'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos)
    throw InputError(path + ": expected little-endian float32 in C order");
  int h = -1, w = -1;
  const std::size_t p = header.find("'shape': (");
  if (p == std::string::npos || std::sscanf(header.c_str() + p, "'shape': (%d, %d)", &h, &w) != 2 || h < 0 || w < 0 ||
      std::uint64_t(h) * std::uint64_t(w) > kMaxImagePixels)
    throw InputError(path + ": expected a 2-D shape of at most " + std::to_string(kMaxImagePixels) + " pixels");
  const std::size_t bytes = std::size_t(h) * std::size_t(w) * sizeof(float);
  if (s.size() != 10 + len + bytes) throw InputError(path + ": data size does not match the shape");
  if (!little_endian()) throw InputError(path + ": reading needs a little-endian machine");
  Image<float> img(w, h);
  if (bytes) std::memcpy(img.data.data(), s.data() + 10 + len, bytes);
  return img;
}

DatasetExport::DatasetExport(std::string dir, const SemanticClasses& classes, const CameraIntrinsics& intrinsics)
    : dir_(std::move(dir)), classes_(classes), K_(intrinsics) {
  if (!dir_.empty() && dir_.back() != '/') dir_ += '/';
  for (const char* sub : {"images", "depth", "labels", "instances"}) std::filesystem::create_directories(dir_ + sub);
}

nlohmann::json DatasetExport::write(const LabelledFrame& f, const std::string& name) {
  const CameraIntrinsics& K = f.intrinsics;
  if (K.width_px != K_.width_px || K.height_px != K_.height_px || K.fx_px != K_.fx_px || K.fy_px != K_.fy_px ||
      K.cx_px != K_.cx_px || K.cy_px != K_.cy_px)  // the pinhole is shared; the range may differ
    throw std::invalid_argument("dataset export: frame " + name + " has other intrinsics than the dataset's");
  const int W = K.width_px, H = K.height_px;
  if (f.rgb.width != W || f.rgb.height != H || f.depth_m.width != W || f.depth_m.height != H || f.class_id.width != W ||
      f.class_id.height != H || f.instance.width != W || f.instance.height != H)
    throw std::invalid_argument("dataset export: frame " + name + " has images of another size than its intrinsics");
  datasets::EncodedFrame e;
  try {
    e = datasets::encode_frame(f, classes_, datasets::InstanceEncoding::kIds16);
  } catch (const std::invalid_argument& ex) {
    throw std::invalid_argument("dataset export: frame " + name + ": " + ex.what());
  }
  write_png(dir_ + "images/" + name + ".png", f.rgb);
  write_png_gray16(dir_ + "depth/" + name + ".png", e.depth_mm);
  write_npy_float32(dir_ + "depth/" + name + ".npy", f.depth_m);
  write_png(dir_ + "labels/" + name + ".png", e.labels);
  write_png_gray16(dir_ + "instances/" + name + ".png", e.instance_ids);
  nlohmann::json M = nlohmann::json::array();
  const Eigen::Matrix4d c2w = opengl_camera_to_world(f.T_world_camera);
  for (int r = 0; r < 4; ++r) M.push_back({c2w(r, 0), c2w(r, 1), c2w(r, 2), c2w(r, 3)});
  return {{"file_path", "images/" + name + ".png"},
          {"transform_matrix", M},
          {"depth_file_path", "depth/" + name + ".png"},
          {"depth_npy_path", "depth/" + name + ".npy"},
          {"label_path", "labels/" + name + ".png"},
          {"instance_path", "instances/" + name + ".png"}};
}

void DatasetExport::add_train(const LabelledFrame& frame) { train_.push_back(write(frame, frame_name("train", train_.size()))); }

void DatasetExport::add_test(const LabelledFrame& frame) { test_.push_back(write(frame, frame_name("test", test_.size()))); }

nlohmann::json DatasetExport::transforms(const nlohmann::json& frames, const nlohmann::json& about) const {
  return {{"camera_model", "OPENCV"},
          {"fl_x", K_.fx_px},
          {"fl_y", K_.fy_px},
          {"cx", K_.cx_px},
          {"cy", K_.cy_px},
          {"w", K_.width_px},
          {"h", K_.height_px},
          {"k1", 0.0},
          {"k2", 0.0},
          {"p1", 0.0},
          {"p2", 0.0},
          {"depth_unit_scale_factor", 0.001},
          {"canopy",
           {{"about", about},
            {"camera_axes", "OpenGL: +X right, +Y up, +Z back (looks along -Z); transform_matrix is camera-to-world"},
            {"pixel_centres", "pixel (i, j) has its centre at (i + 0.5, j + 0.5)"},
            {"depth", "planar z-depth along the optical axis; PNG: uint16 millimetres, npy: float32 metres; 0 = invalid"},
            {"valid_range_m", {K_.min_range_m, K_.max_range_m}},
            {"depth_noise_k", K_.depth_noise_k},
            {"labels", "class colours of classes.json"},
            {"instances", "uint16 fruit instance id + 1, 0 = no fruit"},
            {"world_up", "+Z"}}},
          {"frames", frames}};
}

void DatasetExport::finish(const nlohmann::json& about) {
  nlohmann::json about_test = about;
  about_test["set"] = "test: held-out views, never mapped; rendered without depth noise, robot hidden";
  nlohmann::json about_train = about;
  about_train["set"] = "train: the frames the map was built from";
  write_json_atomic(dir_ + "transforms.json", transforms(train_, about_train));
  write_json_atomic(dir_ + "transforms_test.json", transforms(test_, about_test));
  nlohmann::json classes = nlohmann::json::array();
  for (int i = 0; i < classes_.size(); ++i) {
    const Rgb8 c = classes_.color(i);
    classes.push_back({{"index", i}, {"name", classes_.names[static_cast<std::size_t>(i)]}, {"color", {c.r, c.g, c.b}}});
  }
  write_json_atomic(dir_ + "classes.json", {{"target", classes_.target}, {"classes", classes}});
}

}  // namespace canopy::datasets
