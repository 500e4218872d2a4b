#include "canopy/video/video.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <filesystem>
#include <fstream>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/camera.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/process.h"
#include "canopy/common/value_text.h"

namespace fs = std::filesystem;

namespace canopy::video {

namespace {
std::string temp_video_path(const std::string& path) { return path + ".partial.mp4"; }

// canopy's videos carry this comment in their metadata, near the start of the file (faststart).
constexpr const char* kVideoComment = "written by canopy";

constexpr Rgb8 kMapBackground{45, 45, 45};
// The chase view's tessellation of cylinders (MuJoCo's default is 28 slices, 16 stacks).
constexpr int kVideoPrimitiveSlices = 12, kVideoPrimitiveStacks = 2;

// An encoder that reads no frame for this long is given up (the run goes on without the
// video). CANOPY_VIDEO_STALL_S overrides it: a test hook, so a test need not wait a minute.
double encoder_stall_timeout_s() {
  if (const char* env = std::getenv("CANOPY_VIDEO_STALL_S")) {
    char* end = nullptr;
    const double v = c_strtod(env, &end);
    if (end != env && *end == '\0' && v > 0.0 && v < 1e6) return v;
  }
  return 60.0;
}
// After its input closed, ffmpeg finishes the file (the last frames, the faststart move).
constexpr double kEncoderFinishTimeout_s = 300.0;

std::string busy_message(const std::string& what, const std::string& path) {
  return what + ": '" + path + "' is busy: another canopy command is writing this video now (choose another name)";
}
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
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (fs::is_directory(parent, ec) && !fs::is_directory(path, ec)) {
    // another run writing the same video (its lock is held) is named as such
    LockFile probe;
    bool busy = false;
    try {
      busy = !probe.try_lock(path + ".lock", what);
    } catch (const IoError&) {
      // no lock file can be made there: the check below names the path and the reason
    }
    if (busy) throw InputError(busy_message(what, path));
  }
  validate_output_path_locked(path, what);
}

void VideoWriter::validate_output_path_locked(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(what + ": '" + path + "' is a folder; give a file name such as run.mp4");
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(parent, ec))
    throw InputError(what + ": cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
  // Only a video canopy wrote may be replaced: a world file or anything else named by mistake
  // is never overwritten. The temporary file is canopy's own name: one left by a killed run
  // (no other run holds the video's lock now) is overwritten, whatever it holds.
  for (const std::string& p : {path, temp_video_path(path)})
    if (fs::is_symlink(fs::symlink_status(p, ec)))
      throw InputError(what + ": '" + p + "' is a symbolic link; canopy does not write through it (remove it or "
                       "choose another name)");
  if (fs::exists(path, ec) && !is_canopy_video(path))
    throw InputError(what + ": '" + path + "' exists and is not a video canopy wrote; canopy does not overwrite it "
                     "(remove it or choose another name)");
  if (fs::exists(temp_video_path(path), ec) && !fs::is_regular_file(temp_video_path(path), ec))
    throw InputError(what + ": '" + temp_video_path(path) + "' is not a file; remove it");
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
  // One run writes a video at a time: a second run naming the same file is refused while the
  // first holds the lock (both would write the same temporary file).
  if (!lock_.try_lock(path_ + ".lock", "--video")) throw InputError(busy_message("--video", path_));
  validate_output_path_locked(path_, "--video");
  tmp_path_ = temp_video_path(path_);
  PipedProcessOptions options;
  options.stop = [] { return interrupt_requested(); };
  options.stall_timeout_s = encoder_stall_timeout_s();
  options.finish_timeout_s = kEncoderFinishTimeout_s;
  encoder_ = std::make_unique<PipedProcess>(std::vector<std::string>{
      "ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "bgr24", "-s",
      std::to_string(width) + "x" + std::to_string(height), "-r", format_number(fps, NumberFormat::kDigits9), "-i", "-", "-c:v", "libx264",
      "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p", "-metadata", std::string("comment=") + kVideoComment,
      "-movflags", "+faststart", tmp_path_}, options);
  if (!encoder_->started())
    throw InputError("--video: cannot start ffmpeg (" + encoder_->wait().error +
                     "); apt-get install ffmpeg, or run tools/deps.sh");
  sender_ = std::thread([this] { send_frames(); });
}

VideoWriter::~VideoWriter() {
  stop_sender();
  if (encoder_) {
    encoder_->wait();
    std::error_code ec;
    fs::remove(tmp_path_, ec);
  }
}

void VideoWriter::send_frames() {
  for (;;) {
    std::vector<std::uint8_t> frame;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopped, all sent
      frame = std::move(queue_.front());
      queue_.pop_front();
      sending_ = true;
    }
    // ffmpeg converts BGR to YUV for about 0.7 ms less CPU per 640x480 frame than RGB (libswscale's
    // paths; measured over 2000 frames); the swap runs here, beside the mission.
    for (std::size_t i = 0; i + 2 < frame.size(); i += 3) std::swap(frame[i], frame[i + 2]);
    const bool sent = encoder_->write(frame.data(), frame.size());
    {
      std::lock_guard<std::mutex> lock(mutex_);
      sending_ = false;
      spare_.push_back(std::move(frame));
      if (sent) {
        ++sent_;
      } else {
        broken_ = true;
        queue_.clear();
      }
    }
    changed_.notify_all();
    if (!sent) return;
  }
}

void VideoWriter::stop_sender() {
  if (!sender_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  sender_.join();
}

void VideoWriter::failed_sending() {
  stop_sender();
  fail("ffmpeg stopped reading frames after " + std::to_string(frames()) + " (" + encoder_->wait().describe() + ")");
}

void VideoWriter::fail(const std::string& why) {
  if (error_.empty()) error_ = why;
  stop_sender();
  if (encoder_) encoder_->wait();
  std::error_code ec;
  fs::remove(tmp_path_, ec);
}

int VideoWriter::frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_;
}

void VideoWriter::write(const Image<Rgb8>& frame) {
  CANOPY_CHECK(frame.width == width_ && frame.height == height_, "video frame size changed");
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be packed");
  if (!ok() || !encoder_) return;
  std::vector<std::uint8_t> copy;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return queue_.size() < kQueueFrames || broken_; });
    if (broken_) {
      lock.unlock();
      failed_sending();
      return;
    }
    if (!spare_.empty()) {  // a buffer the sender is done with
      copy = std::move(spare_.front());
      spare_.pop_front();
    }
  }
  const std::size_t bytes = frame.data.size() * sizeof(Rgb8);
  copy.resize(bytes);
  std::memcpy(copy.data(), frame.data.data(), bytes);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(copy));
  }
  changed_.notify_all();
}

void VideoWriter::flush() {
  if (!ok() || !encoder_) return;
  bool broken = false;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return (queue_.empty() && !sending_) || broken_; });
    broken = broken_;
  }
  if (broken) failed_sending();
}

bool VideoWriter::close() {
  if (!encoder_) return ok();
  flush();
  stop_sender();
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
  const double yaw = std::round(base.yaw_rad * 1e3) * 1e-3;
  const Vec3 heading(std::cos(yaw), std::sin(yaw), 0.0);
  const Vec3 ground(std::round(base.x_m * 1e3) * 1e-3, std::round(base.y_m * 1e3) * 1e-3, 0.0);
  return look_at(ground - 1.6 * heading + Vec3(0, 0, 1.9), ground + 0.9 * heading + Vec3(0, 0, 0.6));
}

BasePose chase_camera_base(const BasePose& camera_base, const BasePose& base) {
  constexpr double kDeadBand_m = 0.003, kDeadBand_rad = 0.003;
  const bool moved = std::hypot(base.x_m - camera_base.x_m, base.y_m - camera_base.y_m) > kDeadBand_m ||
                     std::abs(std::remainder(base.yaw_rad - camera_base.yaw_rad, 2.0 * M_PI)) > kDeadBand_rad;
  return moved ? base : camera_base;
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
  chase_k_ = k;
  sim::RenderOptions ro;  // no shadows, no self filter
  // Coarser cylinders than the wrist camera's (docs/mission.md, "The video": the robot pass in
  // about 0.4x its time).
  ro.primitive_slices = kVideoPrimitiveSlices;
  ro.primitive_stacks = kVideoPrimitiveStacks;
  renderer_ = std::make_unique<sim::Renderer>(sim, k, ro);
  const auto rect = map_inset_rect();
  map_ = Image<Rgb8>(rect[2], rect[3], kMapBackground);  // empty until the first view
}

std::array<int, 4> MissionVideo::map_inset_rect() const {
  const int w = chase_k_.width_px, h = chase_k_.height_px;
  const int iw = w / 4, ih = iw * h / w;
  return {8, h - ih - 8, iw, ih};
}

void MissionVideo::tick(sim::Simulator& sim, const std::string& caption) {
  if (!writer_.ok()) return;  // the encoder died: the run goes on without the video
  camera_base_ = camera_base_ ? chase_camera_base(*camera_base_, sim.base_pose()) : sim.base_pose();
  Image<Rgb8> frame = renderer_->render_video_frame(chase_pose(*camera_base_), caption);
  const Rgb8 white{255, 255, 255};
  if (!wrist_rgb_.empty()) {
    const int iw = frame.width / 4, ih = iw * wrist_rgb_.height / std::max(1, wrist_rgb_.width);
    blit_scaled(wrist_rgb_, frame.width - iw - 8, frame.height - 2 * ih - 16, iw, ih, &frame, 2, white);
    blit_scaled(wrist_labels_, frame.width - iw - 8, frame.height - ih - 8, iw, ih, &frame, 2, white);
  }
  const auto [mx, my, mw, mh] = map_inset_rect();
  blit_scaled(map_, mx, my, mw, mh, &frame, 2, white);
  writer_.write(frame);
}

void MissionVideo::set_wrist(const LabelledFrame& f) {
  // The insets are drawn at their final size once here, so each tick only copies them.
  const int iw = chase_k_.width_px / 4, ih = iw * f.rgb.height / std::max(1, f.rgb.width);
  Image<Rgb8> labels(f.class_id.width, f.class_id.height);
  for (std::size_t i = 0; i < f.class_id.data.size(); ++i) labels.data[i] = classes_.color(f.class_id.data[i]);
  wrist_rgb_ = Image<Rgb8>(iw, ih);
  wrist_labels_ = Image<Rgb8>(iw, ih);
  blit_scaled(f.rgb, 0, 0, iw, ih, &wrist_rgb_);
  blit_scaled(labels, 0, 0, iw, ih, &wrist_labels_);
}

void MissionVideo::set_map(const mapping::SemanticOcTree& map, const BasePose& base) {
  const auto [mx, my, mw, mh] = map_inset_rect();
  (void)mx;
  (void)my;
  CameraIntrinsics k = chase_k_;
  const double s = static_cast<double>(mh) / chase_k_.height_px;
  k.width_px = mw;
  k.height_px = mh;
  k.fx_px *= s;
  k.fy_px *= s;
  k.cx_px = 0.5 * mw;
  k.cy_px = 0.5 * mh;
  map_ = map_view(map, classes_, k, chase_pose(base));
}

Image<Rgb8> map_view(const mapping::SemanticOcTree& map, const SemanticClasses& classes, const CameraIntrinsics& k,
                     const Pose& T_world_camera) {
  Image<Rgb8> image(k.width_px, k.height_px, kMapBackground);
  Image<float> zbuf(k.width_px, k.height_px, std::numeric_limits<float>::infinity());
  const Pose T_camera_world = T_world_camera.inverse();
  const double res = map.getResolution();
  std::vector<Rgb8> colour(static_cast<std::size_t>(classes.size()));
  for (int c = 0; c < classes.size(); ++c) colour[static_cast<std::size_t>(c)] = classes.color(c);
  map.for_each_voxel_if([](const mapping::SemanticState& st) { return st.occupancy_logodds() > 0.f; },
                        [&](const octomap::OcTreeKey& key, const mapping::SemanticState& st) {
                          const Vec3 p = T_camera_world * map.center_of(key);
                          if (p.z() < 0.05) return;
                          const double u = k.fx_px * p.x() / p.z() + k.cx_px, v = k.fy_px * p.y() / p.z() + k.cy_px;
                          const double half = std::max(0.5, 0.5 * k.fy_px * res / p.z());
                          const int x0 = std::max(0, static_cast<int>(std::floor(u - half + 0.5)));
                          const int x1 = std::min(k.width_px - 1, static_cast<int>(std::floor(u + half - 0.5)));
                          const int y0 = std::max(0, static_cast<int>(std::floor(v - half + 0.5)));
                          const int y1 = std::min(k.height_px - 1, static_cast<int>(std::floor(v + half - 0.5)));
                          const int c = st.most_likely_class();
                          const Rgb8 col = c >= 0 && c < classes.size() ? colour[static_cast<std::size_t>(c)] : Rgb8{255, 255, 255};
                          const float z = static_cast<float>(p.z());
                          for (int y = y0; y <= y1; ++y)
                            for (int x = x0; x <= x1; ++x)
                              if (z < zbuf.at(x, y)) {
                                zbuf.at(x, y) = z;
                                image.at(x, y) = col;
                              }
                        });
  return image;
}

}  // namespace canopy::video
