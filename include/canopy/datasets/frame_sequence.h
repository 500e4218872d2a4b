#pragma once
// Recorded RGB-D sequences read from files, for mapping without the simulator:
//  - canopy layout: what `canopy render` writes, one folder per frame (rgb.png, depth.png in
//    16-bit millimetres, optional labels.png, frame.json with intrinsics, valid range, pose
//    and class names); `dir` is one such folder or holds them as sub-folders (name order);
//  - TUM RGB-D layout: rgb.txt and depth.txt ("timestamp file" lines), groundtruth.txt
//    ("timestamp tx ty tz qx qy qz qw", the optical frame's pose in the world), 16-bit depth
//    PNGs at depth_scale_per_m units per metre (5000), and intrinsics from a small YAML
//    (camera.yaml in `dir` unless named). RGB and depth are paired one-to-one by nearest
//    timestamp within a tolerance; each pair takes the ground-truth pose nearest to its depth
//    timestamp within the same tolerance. Label images, when used, are labels/<rgb name>.
// Label images are decoded with a class-colour table (by default each class's drawing
// colour, SemanticClasses::color, which is what labels.png holds).
// Malformed files throw InputError naming the file (and line); frames without a depth
// partner, without a pose or without one valid depth pixel are skipped and counted.

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"

namespace canopy::datasets {

/// How a sequence is read.
struct FrameReaderOptions {
  std::string intrinsics_file;    ///< TUM: camera YAML; "" = <dir>/camera.yaml.
  std::string label_colors_file;  ///< Class-colour table YAML; "" = the classes' drawing colours.
  bool label_images = false;      ///< Read a label image per frame (labels.png / labels/<name>).
  double max_time_diff_s = 0.02;  ///< TUM: largest RGB-depth and depth-pose time difference.
};

/// Which layout a folder holds.
enum class FrameLayout { kCanopy, kTum };
const char* to_string(FrameLayout layout);

/// The camera of a TUM sequence: intrinsics, valid range and depth units (camera YAML keys
/// width_px height_px fx_px fy_px cx_px cy_px, required, and min_range_m max_range_m
/// depth_scale_per_m; the intrinsics' keys and limits are CameraIntrinsics::visit's).
struct RecordedCamera {
  CameraIntrinsics intrinsics;
  double depth_scale_per_m = 5000.0;  ///< Depth PNG units per metre (TUM: 5000).
  /// Loads and validates a camera YAML; throws InputError naming the file and key.
  static RecordedCamera load(const std::string& path);

  /// The keys of a camera YAML: the intrinsics' (but depth_noise_k, which only the renderer
  /// uses) and the depth units.
  template <class Archive>
  void visit(Archive& a) {
    intrinsics.visit(a);
    a("depth_scale_per_m", depth_scale_per_m, limits::positive(), "Depth PNG units per metre (TUM: 5000)");
  }
};

/// Checks the intrinsics of a recorded camera against CameraIntrinsics::visit's limits (any
/// principal point in the image, unlike the renderer's); throws InputError naming `where` and
/// the key.
void validate_recorded_intrinsics(const CameraIntrinsics& K, const std::string& where);

/// Class names and the colour of each in label images.
struct ClassColorTable {
  SemanticClasses classes;
  std::vector<Rgb8> colors;  ///< One per class.
  /// The classes' drawing colours.
  static ClassColorTable from_classes(const SemanticClasses& classes);
  /// YAML: `classes: [background, ...]`, optional `target`, `colors: {name: [r, g, b]}`.
  static ClassColorTable load(const std::string& path);
  /// Class index of each pixel; a colour not in the table throws InputError naming the
  /// colour, the pixel and `file`.
  Image<std::uint8_t> decode(const Image<Rgb8>& image, const std::string& file) const;
};

/// One line of rgb.txt / depth.txt.
struct TimedFile {
  double t_s = 0.0;
  std::string file;  ///< As written, relative to the sequence folder.
  int line = 0;
};
/// Reads a TUM file list; throws InputError naming file and line on a malformed line.
std::vector<TimedFile> read_tum_file_list(const std::string& path);

/// One pose of groundtruth.txt.
struct TimedPose {
  double t_s = 0.0;
  Pose T_world_camera = Pose::Identity();
};
/// Reads a TUM trajectory; throws InputError naming file and line on a malformed line or a
/// quaternion whose norm is not 1 within 1e-3.
std::vector<TimedPose> read_tum_trajectory(const std::string& path);

/// One-to-one pairs (i, j) of times a[i], b[j] with |a[i] - b[j]| <= max_diff_s, closest
/// first (as TUM's associate.py), returned in increasing i. Inputs need not be sorted.
std::vector<std::pair<std::size_t, std::size_t>> associate_timestamps(const std::vector<double>& a,
                                                                      const std::vector<double>& b,
                                                                      double max_diff_s);
/// Index of the time in `sorted_t` nearest to `t` if within max_diff_s, else -1.
long nearest_timestamp(const std::vector<double>& sorted_t, double t, double max_diff_s);

/// A frame that will not be mapped, and why.
struct SkippedFrame {
  std::string name;
  std::string reason;
};

/// A recorded sequence opened for reading, one frame at a time.
class FrameSequence {
 public:
  /// Detects the layout and reads the lists (not the images). Throws InputError when `dir`
  /// is missing, holds neither layout or has a malformed file.
  static FrameSequence open(const std::string& dir, const FrameReaderOptions& options = {});

  FrameLayout layout() const { return layout_; }
  const std::string& dir() const { return dir_; }
  const SemanticClasses& classes() const { return table_.classes; }
  /// Frames to read (the ones skipped while opening are not among them).
  std::size_t size() const { return frames_.size(); }
  const std::string& name(std::size_t i) const { return frames_[i].name; }
  /// Frames dropped while opening (no depth partner, no pose).
  const std::vector<SkippedFrame>& skipped() const { return skipped_; }
  /// What the reader changed or assumed (e.g. frames sorted into time order), for the log.
  const std::vector<std::string>& notes() const { return notes_; }

  /// Reads frame i into `frame` (labels in class_id when label_images is set). Returns false
  /// with `why` when the frame has no valid depth in range; throws InputError on a bad file
  /// (wrong PNG format or size, unknown label colour).
  bool read(std::size_t i, LabelledFrame* frame, std::string* why) const;

 private:
  struct Entry {
    std::string name;
    std::string rgb, depth, labels;  ///< Paths.
    CameraIntrinsics intrinsics;
    double depth_scale_per_m = 1000.0;
    Pose T_world_camera = Pose::Identity();
  };
  FrameLayout layout_ = FrameLayout::kCanopy;
  std::string dir_;
  FrameReaderOptions options_;
  ClassColorTable table_;
  std::vector<Entry> frames_;
  std::vector<SkippedFrame> skipped_;
  std::vector<std::string> notes_;

  static FrameSequence open_canopy(const std::string& dir, const std::vector<std::string>& folders,
                                   const FrameReaderOptions& options);
  static FrameSequence open_tum(const std::string& dir, const FrameReaderOptions& options);
};

/// Counts of skip reasons ("no depth within 0.02 s": 3, ...).
std::map<std::string, int> count_reasons(const std::vector<SkippedFrame>& skipped);

}  // namespace canopy::datasets
