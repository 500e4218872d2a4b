#include "canopy/mission/video.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/process.h"

namespace fs = std::filesystem;

namespace canopy {

namespace {
std::string temp_video_path(const std::string& path) { return path + ".partial.mp4"; }
}  // namespace

void VideoWriter::validate_output_path(const std::string& path, const std::string& what) {
  if (path.empty()) throw InputError(what + ": the video file name is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(what + ": '" + path + "' is a folder; give a file name such as run.mp4");
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(parent, ec))
    throw InputError(what + ": cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
  // Creating the encoder's temporary file is the only reliable test (root ignores modes;
  // read-only mounts do not show in them).
  const std::string probe = temp_video_path(path);
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(what + ": cannot write '" + path + "': " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

VideoWriter::VideoWriter(std::string path, int width, int height, double fps)
    : path_(std::move(path)), width_(width), height_(height) {
  if (width % 2 || height % 2) throw InputError("--video: frame size must be even for H.264");
  if (!(fps > 0.0 && fps <= 240.0)) throw InputError("--video-fps: value '" + std::to_string(fps) + "' must be in (0, 240]");
  validate_output_path(path_);
  tmp_path_ = temp_video_path(path_);
  encoder_ = std::make_unique<PipedProcess>(std::vector<std::string>{
      "ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s",
      std::to_string(width) + "x" + std::to_string(height), "-r", std::to_string(fps), "-i", "-", "-c:v", "libx264",
      "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p", tmp_path_});
  if (!encoder_->started())
    throw InputError("--video: cannot start ffmpeg (" + encoder_->wait().error +
                     "); apt-get install ffmpeg, or run tools/deps.sh");
}

VideoWriter::~VideoWriter() {
  if (encoder_) {
    encoder_->wait();
    std::error_code ec;
    fs::remove(tmp_path_, ec);
  }
}

void VideoWriter::fail(const std::string& why) {
  if (error_.empty()) error_ = why;
  if (encoder_) encoder_->wait();
  std::error_code ec;
  fs::remove(tmp_path_, ec);
}

void VideoWriter::write(const Image<Rgb8>& frame) {
  CANOPY_CHECK(frame.width == width_ && frame.height == height_, "video frame size changed");
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be packed");
  if (!ok() || !encoder_) return;
  if (!encoder_->write(frame.data.data(), frame.data.size() * sizeof(Rgb8))) {
    fail("ffmpeg stopped reading frames after " + std::to_string(frames_) + " (" + encoder_->wait().describe() + ")");
    return;
  }
  ++frames_;
}

bool VideoWriter::close() {
  if (!encoder_) return ok();
  if (ok()) {
    const ProcessStatus status = encoder_->wait();
    if (!status.ok()) {
      fail("ffmpeg failed writing " + path_ + " (" + status.describe() + ")");
    } else {
      std::error_code ec;
      fs::rename(tmp_path_, path_, ec);
      if (ec) fail("cannot move " + tmp_path_ + " to " + path_ + ": " + ec.message());
    }
  }
  encoder_.reset();
  return ok();
}

}  // namespace canopy
