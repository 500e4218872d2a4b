#include "canopy/mission/video.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/common/camera.h"
#include "canopy/common/process.h"

namespace fs = std::filesystem;

namespace canopy::mission {

namespace {
std::string temp_video_path(const std::string& path) { return path + ".partial.mp4"; }

// canopy's videos carry this comment in their metadata, near the start of the file (faststart).
constexpr const char* kVideoComment = "written by canopy";
}  // namespace

bool VideoWriter::is_canopy_video(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string head(12, '\0');
  if (!in.read(head.data(), 12) || head.compare(4, 4, "ftyp") != 0) return false;  // not an MP4
  const std::string needle = kVideoComment;
  std::string window = head, chunk(1 << 16, '\0');
  std::size_t scanned = 12;
  while (scanned < (std::size_t(16) << 20)) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const std::size_t got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    window = window.substr(window.size() > needle.size() ? window.size() - needle.size() : 0) + chunk.substr(0, got);
    if (window.find(needle) != std::string::npos) return true;
    scanned += got;
  }
  return false;
}

void VideoWriter::validate_output_path(const std::string& path, const std::string& what) {
  if (path.empty()) throw InputError(what + ": the video file name is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(what + ": '" + path + "' is a folder; give a file name such as run.mp4");
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(parent, ec))
    throw InputError(what + ": cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
  // Only a video canopy wrote may be replaced: a world file or anything else named by mistake
  // is never overwritten.
  for (const std::string& p : {path, temp_video_path(path)})
    if (fs::exists(p, ec) && !is_canopy_video(p))
      throw InputError(what + ": '" + p + "' exists and is not a video canopy wrote; canopy does not overwrite it "
                       "(remove it or choose another name)");
  // Creating the encoder's temporary file is the only reliable test (root ignores modes;
  // read-only mounts do not show in them).
  const std::string probe = temp_video_path(path);
  if (fs::exists(probe, ec)) return;  // a video of ours, left by an interrupted run: writable as it is
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
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
      "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p", "-metadata", std::string("comment=") + kVideoComment,
      "-movflags", "+faststart", tmp_path_});
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

Pose chase_pose(const BasePose& base) {
  const Vec3 heading(std::cos(base.yaw_rad), std::sin(base.yaw_rad), 0.0);
  const Vec3 ground(base.x_m, base.y_m, 0.0);
  return look_at(ground - 1.6 * heading + Vec3(0, 0, 1.9), ground + 0.9 * heading + Vec3(0, 0, 0.6));
}

MissionVideo::MissionVideo(const std::string& path, int w, int h, double fps, sim::Simulator& sim,
                           const SemanticClasses& classes)
    : writer_(path, w, h, fps), classes_(classes) {
  CameraIntrinsics k;
  k.width_px = w;
  k.height_px = h;
  k.cx_px = 0.5 * w;
  k.cy_px = 0.5 * h;
  k.fx_px = k.fy_px = 0.5 * h / std::tan(0.5 * 60.0 * M_PI / 180.0);  // 60 degree vertical field of view
  k.min_range_m = 0.01;
  k.max_range_m = 50.0;
  renderer_ = std::make_unique<sim::Renderer>(sim, k, sim::RenderOptions{true, 1, false});
}

void MissionVideo::tick(sim::Simulator& sim, const std::string& caption) {
  if (!writer_.ok()) return;  // the encoder died: the run goes on without the video
  Image<Rgb8> frame = renderer_->render_captioned(chase_pose(sim.base_pose()), true, caption);
  if (!wrist_rgb_.empty()) {
    const int iw = frame.width / 4, ih = iw * wrist_rgb_.height / std::max(1, wrist_rgb_.width);
    const Rgb8 white{255, 255, 255};
    blit_scaled(wrist_rgb_, frame.width - iw - 8, frame.height - 2 * ih - 16, iw, ih, &frame, 2, white);
    blit_scaled(wrist_labels_, frame.width - iw - 8, frame.height - ih - 8, iw, ih, &frame, 2, white);
  }
  writer_.write(frame);
}

void MissionVideo::set_wrist(const LabelledFrame& f) {
  wrist_rgb_ = f.rgb;
  wrist_labels_ = Image<Rgb8>(f.class_id.width, f.class_id.height);
  for (std::size_t i = 0; i < f.class_id.data.size(); ++i) wrist_labels_.data[i] = classes_.color(f.class_id.data[i]);
}

}  // namespace canopy::mission
