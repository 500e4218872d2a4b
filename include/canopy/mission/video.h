#pragma once
// The mission's video: a chase view of the robot with the wrist camera's last RGB and label
// images inset and a caption line (MissionVideo), written to an H.264 MP4 by streaming raw
// frames to ffmpeg (Debian's ffmpeg), started without a shell (common/process.h).

#include <memory>
#include <string>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"
#include "canopy/common/image.h"
#include "canopy/sim/renderer.h"

namespace canopy {
class PipedProcess;
}

namespace canopy::mission {

/// Streams same-sized RGB frames into an MP4 file. The file appears under its final name
/// only after close() succeeds. An encoder that dies mid-run does not end the caller's
/// run: write() then drops frames, ok() turns false and error() says why.
class VideoWriter {
 public:
  /// Checks the output path (validate_output_path) and starts ffmpeg; throws InputError
  /// when the path is unusable or ffmpeg is missing or cannot start.
  VideoWriter(std::string path, int width, int height, double fps);
  ~VideoWriter();  ///< Closes without publishing the file if close() was not called.
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Throws InputError (prefixed with `what`, naming the path) unless `path` can be
  /// written as a video: not a folder, in an existing folder where a file can be created, and
  /// either absent or a video canopy wrote (anything else is never overwritten).
  /// Call it before a long run so a bad path fails at once.
  static void validate_output_path(const std::string& path, const std::string& what = "--video");
  /// True when `path` is an MP4 this class wrote (its metadata carries canopy's comment).
  static bool is_canopy_video(const std::string& path);

  /// Appends one frame (must match the size given at construction). After an encoder
  /// failure the frame is dropped; nothing throws.
  void write(const Image<Rgb8>& frame);
  /// Finishes encoding and moves the file into place. Returns ok(); never throws for an
  /// encoder failure.
  bool close();
  /// Frames the encoder accepted.
  int frames() const { return frames_; }
  /// False once the encoder has failed (or publishing the file failed).
  bool ok() const { return error_.empty(); }
  /// Why the video is missing ("" while ok()).
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }

 private:
  void fail(const std::string& why);

  std::string path_, tmp_path_;
  int width_, height_;
  std::unique_ptr<PipedProcess> encoder_;
  int frames_ = 0;
  std::string error_;
};

/// Off-screen video of a mission: every tick renders the chase view with the last wrist
/// frame's RGB and labels inset and the caption, and appends it to the MP4.
class MissionVideo {
 public:
  /// Starts the encoder (VideoWriter's errors); frames of `width` x `height` at `fps`.
  MissionVideo(const std::string& path, int width, int height, double fps, sim::Simulator& sim,
               const SemanticClasses& classes);
  /// Renders and writes one frame (nothing once the encoder has failed).
  void tick(sim::Simulator& sim, const std::string& caption);
  /// The wrist frame shown in the insets from now on.
  void set_wrist(const LabelledFrame& frame);
  VideoWriter& writer() { return writer_; }

 private:
  VideoWriter writer_;
  SemanticClasses classes_;
  std::unique_ptr<sim::Renderer> renderer_;
  Image<Rgb8> wrist_rgb_, wrist_labels_;
};

/// The chase camera: behind and above the base, looking ahead along the aisle.
Pose chase_pose(const BasePose& base);

}  // namespace canopy::mission
