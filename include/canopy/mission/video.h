#pragma once
// Writes RGB frames to an H.264 MP4 by streaming raw frames to ffmpeg (Debian's ffmpeg),
// started without a shell (common/process.h).

#include <memory>
#include <string>

#include "canopy/common/image.h"

namespace canopy {

class PipedProcess;

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
  /// written as a video: not a folder, in an existing folder where a file can be created.
  /// Call it before a long run so a bad path fails at once.
  static void validate_output_path(const std::string& path, const std::string& what = "--video");

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

}  // namespace canopy
