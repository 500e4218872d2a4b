#include "canopy/common/video.h"

#include <cstdlib>
#include <filesystem>

#include "canopy/common/error.h"

namespace canopy {

namespace {
std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}
}  // namespace

VideoWriter::VideoWriter(std::string path, int width, int height, double fps)
    : path_(std::move(path)), width_(width), height_(height) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0)
    throw InputError("--video: ffmpeg is not installed (apt-get install ffmpeg, or run tools/deps.sh)");
  if (width % 2 || height % 2) throw InputError("--video: frame size must be even for H.264");
  if (!(fps > 0.0 && fps <= 240.0)) throw InputError("--video-fps: value '" + std::to_string(fps) + "' must be in (0, 240]");
  tmp_path_ = path_ + ".partial.mp4";
  const std::string cmd = "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " + std::to_string(width) + "x" +
                          std::to_string(height) + " -r " + std::to_string(fps) +
                          " -i - -c:v libx264 -preset veryfast -crf 20 -pix_fmt yuv420p " + shell_quote(tmp_path_);
  pipe_ = popen(cmd.c_str(), "w");
  if (!pipe_) throw InputError("--video: cannot start ffmpeg");
}

VideoWriter::~VideoWriter() {
  if (pipe_) {
    pclose(pipe_);
    std::error_code ec;
    std::filesystem::remove(tmp_path_, ec);
  }
}

void VideoWriter::write(const Image<Rgb8>& frame) {
  CANOPY_CHECK(frame.width == width_ && frame.height == height_, "video frame size changed");
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be packed");
  if (std::fwrite(frame.data.data(), 3, frame.data.size(), pipe_) != frame.data.size())
    throw std::runtime_error("ffmpeg stopped accepting frames for " + path_);
  ++frames_;
}

void VideoWriter::close() {
  if (!pipe_) return;
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  if (status != 0) throw std::runtime_error("ffmpeg failed writing " + path_);
  std::filesystem::rename(tmp_path_, path_);
}

}  // namespace canopy
