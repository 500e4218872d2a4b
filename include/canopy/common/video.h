#pragma once
// Writes RGB frames to an H.264 MP4 by piping raw frames to ffmpeg (Debian's ffmpeg).

#include <cstdio>
#include <string>

#include "canopy/common/image.h"

namespace canopy {

/// Streams same-sized RGB frames into an MP4 file. The file appears under its final name
/// only after close() succeeds.
class VideoWriter {
 public:
  /// Starts ffmpeg; throws InputError when ffmpeg is missing or cannot start.
  VideoWriter(std::string path, int width, int height, double fps);
  ~VideoWriter();  ///< Closes without publishing the file if close() was not called.
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Appends one frame (must match the size given at construction).
  void write(const Image<Rgb8>& frame);
  /// Finishes encoding and moves the file into place; throws on ffmpeg failure.
  void close();
  int frames() const { return frames_; }

 private:
  std::string path_, tmp_path_;
  int width_, height_;
  FILE* pipe_ = nullptr;
  int frames_ = 0;
};

}  // namespace canopy
