#pragma once
// A lab's ROS 2 recording (MCAP) as a recorded sequence for jobs::map_recorded: what `canopy map
// --mcap` maps. RealSense (/camera/color/image_raw, /camera/aligned_depth_to_color/image_raw,
// /camera/color/camera_info) and ZED conventions, canopy's own topics, 16UC1 / mono16 (mm) and
// 32FC1 (m; NaN, inf and 0: no return) depth, rgb8 / bgr8 / rgba8 / bgra8 or PNG CompressedImage
// colour, mono8 class labels, /tf and /tf_static.
//
// Read in two passes, streamed (memory does not grow with the recording): the first reads
// camera_info, the transforms and the image headers (pixels passed over), pairs each depth
// image with the colour (and label) image whose stamp is nearest within max_dt and takes its
// pose from the tree at the depth's stamp; the second reads the images again, on a thread of
// its own, and hands over one frame at a time as map_recorded asks for it. Refusals (InputError,
// one line naming the file, the topic or the frame; nothing written) are those of `map-bag`.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
#include "canopy/jobs/recorded_map_job.h"

namespace canopy::jobs {

/// Which topics and frames of a recording to map; "" is chosen from the recording.
struct McapFrameOptions {
  std::string rgb;          ///< Colour images (Image or CompressedImage).
  std::string depth;        ///< Depth images registered to the colour ones (aligned).
  std::string camera_info;  ///< The colour camera's CameraInfo.
  std::string labels;       ///< Class-index images (mono8), read with label_images.
  std::string frame;        ///< The optical frame of the depth images; "": their header.frame_id.
  std::string world_frame;  ///< The map's frame; "": the root of the camera's transform tree.
  double max_dt_s = 0.02;   ///< Largest depth-colour (and label) stamp difference; a pose's reach past its samples.
  double min_range_m = CameraIntrinsics{}.min_range_m;  ///< The camera's valid depth range (not in camera_info).
  double max_range_m = CameraIntrinsics{}.max_range_m;
  bool label_images = false;  ///< Read class labels from `labels` (--seg truth).
  SemanticClasses classes;    ///< The labels' classes.
  std::uint64_t max_held_bytes = std::uint64_t(1) << 30;  ///< Images held between partners, at most.
};

/// An MCAP recording opened for mapping (the first pass done).
class McapFrames {
 public:
  /// Opens `path`, chooses what the options leave open and runs the first pass. InputError on a
  /// file that is no ros2 MCAP, truncated or corrupt; a topic missing or of another type, an
  /// encoding canopy does not read, image stamps that do not increase, images whose size is not
  /// camera_info's, a frame absent from the transforms or in another tree.
  McapFrames(const std::string& path, const McapFrameOptions& options);
  ~McapFrames();
  McapFrames(const McapFrames&) = delete;
  McapFrames& operator=(const McapFrames&) = delete;

  /// One line per choice made from the recording ("--depth /camera/...: the only depth topic").
  const std::vector<std::string>& choices() const;
  /// The options with every choice filled in (run.yaml records them).
  const McapFrameOptions& options() const;
  /// The frames to map, for map_recorded; reading them streams the second pass (in order).
  RecordedSequence sequence();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace canopy::jobs
