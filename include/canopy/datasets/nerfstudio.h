#pragma once
// Datasets for neural reconstruction (NeRF, Gaussian splatting) in nerfstudio's layout
// (docs/datasets.md): every frame the robot mapped (the training set, transforms.json) and a
// held-out ring of free-camera views around each plant that mapping never saw (the test set,
// transforms_test.json). Per frame:
//   images/<set>_NNNN.png      8-bit RGB
//   depth/<set>_NNNN.png       16-bit planar z-depth in millimetres (0 = invalid), as
//                              nerfstudio reads it (depth_unit_scale_factor 0.001)
//   depth/<set>_NNNN.npy       the same depth as float32 metres (NumPy .npy, row-major H x W)
//   labels/<set>_NNNN.png      class colours (the table in classes.json)
//   instances/<set>_NNNN.png   16-bit fruit instance id + 1 (0 = no fruit)
// Poses are camera-to-world 4x4 matrices in OpenGL camera axes (+X right, +Y up, +Z back:
// the camera looks along -Z), with shared pinhole intrinsics (pixel centres at i + 0.5).
// Written into a folder the caller stages (StagedDir of kind "dataset"); the held-out views
// are rendered by the jobs that export (jobs/test_views.h).

#include <cstddef>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"
#include "canopy/common/camera.h"
#include "canopy/common/image.h"

namespace canopy::datasets {

/// Camera-to-world matrix in OpenGL camera axes of canopy's optical-frame pose
/// (x right, y down, z forward): T_world_camera with its y and z axes negated.
Eigen::Matrix4d opengl_camera_to_world(const Pose& T_world_camera);

/// Writes a nerfstudio dataset frame by frame into an existing folder.
class DatasetExport {
 public:
  /// `dir` is the (staged) output folder; every frame must share `intrinsics`.
  DatasetExport(std::string dir, const SemanticClasses& classes, const CameraIntrinsics& intrinsics);

  /// Writes a training frame's files (a frame the map was built from).
  void add_train(const LabelledFrame& frame);
  /// Writes a held-out frame's files.
  void add_test(const LabelledFrame& frame);
  /// Writes transforms.json, transforms_test.json and classes.json; `about` is stored under
  /// "canopy" in both transforms files (what run made the frames).
  void finish(const nlohmann::json& about);

  std::size_t train_count() const { return train_.size(); }
  const CameraIntrinsics& intrinsics() const { return K_; }
  std::size_t test_count() const { return test_.size(); }

 private:
  nlohmann::json write(const LabelledFrame& frame, const std::string& name);
  nlohmann::json transforms(const nlohmann::json& frames, const nlohmann::json& about) const;

  std::string dir_;
  SemanticClasses classes_;
  CameraIntrinsics K_;
  nlohmann::json train_ = nlohmann::json::array();
  nlohmann::json test_ = nlohmann::json::array();
};

/// Writes `image` as a NumPy .npy file of float32, shape (height, width), atomically.
void write_npy_float32(const std::string& path, const Image<float>& image);
/// Reads what write_npy_float32 wrote (little-endian float32, C order, 2-D); throws
/// InputError naming the file otherwise.
Image<float> read_npy_float32(const std::string& path);

}  // namespace canopy::datasets
