#pragma once
// The mission's video: a chase view of the robot with the wrist camera's last RGB and label
// images and the growing semantic map inset and a caption line (MissionVideo), written to an
// H.264 MP4 by streaming raw frames to ffmpeg (Debian's ffmpeg), started without a shell
// (common/process.h).

#include <array>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/frame.h"
#include "canopy/common/image.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/sim/renderer.h"

namespace canopy {
class PipedProcess;
}

namespace canopy::video {

/// Streams same-sized RGB frames into an MP4 file. The file appears under its final name
/// only after close() succeeds. An encoder that dies mid-run does not end the caller's
/// run: write() then drops frames, ok() turns false and error() says why.
///
/// Frames reach ffmpeg from a thread of the writer's own, through a queue of a few frames:
/// write() copies the frame and returns while ffmpeg is busy, and waits only when the queue is
/// full. An encoder's failure is noticed by the write(), flush() or close() after it.
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
  /// Call it before a long run so a bad path fails at once. A video another run is writing
  /// now (its `<path>.lock` is held) is refused as busy.
  static void validate_output_path(const std::string& path, const std::string& what = "--video");
  /// True when `path` is an MP4 this class wrote (its metadata carries canopy's comment).
  static bool is_canopy_video(const std::string& path);

  /// Appends one frame (must match the size given at construction). After an encoder
  /// failure the frame is dropped; nothing throws.
  void write(const Image<Rgb8>& frame);
  /// Waits until every frame written so far has reached the encoder, or the encoder failed.
  void flush();
  /// Finishes encoding and moves the file into place. Returns ok(); never throws for an
  /// encoder failure.
  bool close();
  /// Frames the encoder accepted so far (every frame written, once flush() or close() returned
  /// and the encoder did not fail).
  int frames() const;
  /// False once a failure of the encoder was noticed (or publishing the file failed).
  bool ok() const { return error_.empty(); }
  /// Why the video is missing ("" while ok()).
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }

 private:
  static void validate_output_path_locked(const std::string& path, const std::string& what);
  void fail(const std::string& why);
  void send_frames();  // the sender thread
  void stop_sender();  // lets the sender send what is queued, then joins it
  void failed_sending();  // after the sender failed: the encoder's status into error_

  std::string path_, tmp_path_;
  int width_, height_;
  LockFile lock_;  // on <path>.lock while the video is written
  std::unique_ptr<PipedProcess> encoder_;
  std::string error_;  // the caller's thread's

  static constexpr std::size_t kQueueFrames = 8;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<std::uint8_t>> queue_, spare_;  // guarded by mutex_, as are the below
  bool stop_ = false, sending_ = false, broken_ = false;
  int sent_ = 0;
  std::thread sender_;
};

/// Off-screen video of a mission: every tick renders the chase view (without shadows, which
/// would triple its cost) with the caption, insets the last wrist frame's RGB and labels
/// (bottom right) and the map as it was after the last view (bottom left), and appends it to
/// the MP4. The insets are drawn once when they change, not every tick.
class MissionVideo {
 public:
  /// Starts the encoder (VideoWriter's errors); frames of `width` x `height` at `fps`.
  MissionVideo(const std::string& path, int width, int height, double fps, sim::Simulator& sim,
               const SemanticClasses& classes);
  /// Renders and writes one frame (nothing once the encoder has failed).
  void tick(sim::Simulator& sim, const std::string& caption);
  /// The wrist frame shown in the insets from now on.
  void set_wrist(const LabelledFrame& frame);
  /// The map inset from now on: `map`'s occupied voxels in class colours, seen from the chase
  /// camera at `base` (map_view).
  void set_map(const mapping::SemanticOcTree& map, const BasePose& base);
  VideoWriter& writer() { return writer_; }
  /// The map inset's place in the frame (x, y, width, height), inside its 2-pixel border.
  std::array<int, 4> map_inset_rect() const;

 private:
  VideoWriter writer_;
  SemanticClasses classes_;
  std::unique_ptr<sim::Renderer> renderer_;
  CameraIntrinsics chase_k_;
  Image<Rgb8> wrist_rgb_, wrist_labels_, map_;
  std::optional<BasePose> camera_base_;  // the base pose the chase camera stands for
};

/// The chase camera: behind and above the base, looking ahead along the aisle. The base pose
/// is rounded to 1 mm and 1 mrad (0.2 pixel at most in a 640x480 frame).
Pose chase_pose(const BasePose& base);

/// The base pose the chase camera follows: `camera_base` while `base` stays within 3 mm and
/// 3 mrad of it (at most about 1 pixel in a 640x480 frame), else `base`. A standing base
/// jitters (the arm's reactions) across chase_pose's rounding steps; the dead band keeps the
/// camera exactly still, so the world is drawn once per stop rather than at every crossing.
BasePose chase_camera_base(const BasePose& camera_base, const BasePose& base);

/// The occupied voxels of `map` (p_occ > 0.5) as `camera` at `T_world_camera` sees them: each
/// voxel a square of its projected size in its most likely class's colour, nearest in front,
/// on a dark grey background.
Image<Rgb8> map_view(const mapping::SemanticOcTree& map, const SemanticClasses& classes, const CameraIntrinsics& camera,
                     const Pose& T_world_camera);

}  // namespace canopy::video
