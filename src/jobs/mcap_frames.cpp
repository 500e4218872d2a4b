#include "canopy/jobs/mcap_frames.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/common/params.h"
#include "canopy/common/png_io.h"
#include "canopy/jobs/mcap_job.h"
#include "canopy/jobs/mcap_topics.h"
#include "canopy/ros2/cdr.h"
#include "canopy/ros2/mcap_reader.h"
#include "canopy/ros2/tf_buffer.h"

namespace canopy::jobs {

namespace msg = ros2::msg;
namespace topics = recording_topics;

// Named (not anonymous): McapFrames::Impl holds these types.
namespace mcap_frames_detail {

enum Kind { kDepth = 0, kRgb = 1, kLabels = 2, kKinds = 3 };
const char* const kKindFlag[kKinds] = {"--depth", "--rgb", "--labels"};

std::int64_t ns_of(const msg::Time& t) { return std::int64_t(t.sec) * 1000000000 + std::int64_t(t.nanosec); }

std::string seconds(std::int64_t ns) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.9f s", static_cast<double>(ns) / 1e9);
  return buf;
}

std::string list(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s.empty() ? "none" : s;
}

// An image message's header fields, its pixels passed over.
struct ImageHeader {
  std::int64_t stamp_ns = 0;
  std::string frame_id;
  int width = 0, height = 0;
  std::string encoding;  ///< Image's encoding, or CompressedImage's format.
  bool compressed = false;
};

ImageHeader peek_image(const ros2::McapMessage& m, const ros2::McapReader& in) {
  const bool compressed = m.schema && m.schema->name == msg::CompressedImage::kTypeName;
  ImageHeader h;
  h.compressed = compressed;
  try {
    ros2::CdrReader cdr(m.data, compressed ? msg::CompressedImage::kTypeName : msg::Image::kTypeName);
    msg::Header header;
    cdr(header);
    h.stamp_ns = ns_of(header.stamp);
    h.frame_id = header.frame_id;
    if (!compressed) {
      std::uint32_t height = 0, width = 0;
      cdr(height);
      cdr(width);
      cdr(h.encoding);
      h.width = static_cast<int>(std::min<std::uint32_t>(width, 1u << 30));
      h.height = static_cast<int>(std::min<std::uint32_t>(height, 1u << 30));
    } else {
      cdr(h.encoding);
      std::uint32_t n = 0;
      cdr(n);
      const std::size_t at = m.data.size() - cdr.remaining();
      const std::optional<std::pair<int, int>> size =
          is_png(h.encoding) ? png_declared_size(m.data.substr(at, std::min<std::size_t>(n, cdr.remaining())))
                             : std::nullopt;
      if (size) {
        h.width = size->first;
        h.height = size->second;
      }
    }
  } catch (const InputError& e) {
    throw InputError(in.path() + ": " + m.channel->topic + " at log time " + seconds(std::int64_t(m.log_time_ns)) +
                     ": " + e.what());
  }
  return h;
}

// A frame to map: its messages (each topic's ordinal in log-time order), camera and pose.
struct PlannedFrame {
  std::uint32_t part[kKinds] = {0, 0, 0};
  std::string name;
  CameraIntrinsics intrinsics;
  Pose T_world_camera = Pose::Identity();
};

// A frame's message bytes, handed from the reading thread to the mapping one.
struct FrameBytes {
  std::shared_ptr<const std::string> part[kKinds];
};

}  // namespace mcap_frames_detail

using namespace mcap_frames_detail;

struct McapFrames::Impl {
  McapFrameOptions o;
  ros2::McapReader in;
  std::vector<std::string> choices, notes;
  std::string topic[kKinds];
  bool compressed_rgb = false;
  std::string encoding[kKinds];
  std::vector<PlannedFrame> frames;
  std::vector<datasets::SkippedFrame> skipped;
  std::unordered_map<std::uint32_t, int> uses[kKinds];  // how many frames take each message

  // The second pass, on its thread.
  std::thread reader;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<FrameBytes> ready;
  bool cancel = false, done = false;
  std::exception_ptr error;
  std::size_t delivered = 0;

  Impl(const std::string& path, const McapFrameOptions& options) : o(options), in(path) {}

  ~Impl() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      cancel = true;
    }
    changed.notify_all();
    if (reader.joinable()) reader.join();
  }

  [[noreturn]] void refuse(const std::string& what) const { throw InputError(in.path() + ": " + what); }

  std::map<std::string, ros2::McapTopic> topic_map() const {
    std::map<std::string, ros2::McapTopic> m;
    for (const ros2::McapTopic& t : in.topics()) m.emplace(t.topic, t);
    return m;
  }

  // Each image topic's first message's encoding (or format), read until every one is seen.
  std::map<std::string, std::string> first_encodings(const std::map<std::string, ros2::McapTopic>& all) const {
    std::map<std::string, std::string> enc;
    ros2::McapReadOptions only;
    for (const auto& [name, t] : all)
      if ((t.type == msg::Image::kTypeName || t.type == msg::CompressedImage::kTypeName) &&
          t.message_count.value_or(1) > 0)
        only.topics.push_back(name);
    if (only.topics.empty()) return enc;
    only.order = ros2::McapOrder::kFile;
    in.for_each_message(
        [&](const ros2::McapMessage& m) {
          if (!enc.count(m.channel->topic)) enc[m.channel->topic] = peek_image(m, in).encoding;
          return enc.size() < only.topics.size();
        },
        only);
    return enc;
  }

  // What the options leave open, chosen from the recording's topics (mcap_topics.h).
  void choose_topics() {
    const std::map<std::string, ros2::McapTopic> all = topic_map();
    const std::map<std::string, std::string> enc =
        choice_needs_encodings(o) ? first_encodings(all) : std::map<std::string, std::string>{};
    std::vector<RecordingTopic> listed;
    for (const auto& [name, t] : all) {
      const auto e = enc.find(name);
      listed.push_back({name, t.type, e == enc.end() ? "" : e->second});
    }
    try {
      for (std::string& line : choose_mcap_topics(listed, o)) choices.push_back(std::move(line));
    } catch (const InputError& e) {
      refuse(e.what());
    }
    topic[kDepth] = o.depth;
    topic[kRgb] = o.rgb;
    topic[kLabels] = o.label_images ? o.labels : "";
    compressed_rgb = all.at(o.rgb).type == msg::CompressedImage::kTypeName;
  }

  void check_encoding(Kind k, const ImageHeader& h, std::int64_t log_ns) {
    const std::string& e = h.encoding;
    const bool ok = k == kDepth ? is_depth_encoding(e)
                    : k == kRgb ? (h.compressed ? is_png(e) : is_colour_encoding(e))
                                : is_label_encoding(e);
    if (!ok)
      refuse(topic[k] + " at " + seconds(log_ns) + ": " + (h.compressed ? "a CompressedImage of format '" : "encoding '") +
             e + "', which canopy does not read here (" +
             (k == kDepth ? "16UC1, mono16, 32FC1" : k == kRgb ? "rgb8, bgr8, rgba8, bgra8, PNG" : "mono8, 8UC1") + ")");
    if (encoding[k].empty()) encoding[k] = e;
    else if (encoding[k] != e) refuse(topic[k] + ": images of encodings '" + encoding[k] + "' and '" + e + "'");
  }

  // The first pass: camera_info, the transforms, every image's header; then the pairing.
  void first_pass() {
    const std::map<std::string, ros2::McapTopic> all = topic_map();
    ros2::McapReadOptions only;
    for (int k = 0; k < kKinds; ++k)
      if (!topic[k].empty()) only.topics.push_back(topic[k]);
    only.topics.push_back(o.camera_info);
    const auto present = [&](const char* t) { return all.count(t) && all.at(t).message_count.value_or(1) > 0; };
    for (const char* t : {topics::kTf, topics::kTfStatic})
      if (present(t)) only.topics.push_back(t);
    if (!present(topics::kTf) && !present(topics::kTfStatic))
      refuse("no /tf or /tf_static: the camera's pose cannot be known");
    std::vector<ImageHeader> headers[kKinds];
    std::vector<std::pair<std::int64_t, msg::CameraInfo>> infos;
    ros2::TfBuffer tf;
    in.for_each_message(
        [&](const ros2::McapMessage& m) {
          const std::string& t = m.channel->topic;
          if (t == topics::kTf || t == topics::kTfStatic) {
            tf.add(in.decode<msg::TFMessage>(m), t == topics::kTfStatic,
                   in.path() + ": " + t + " at " + seconds(std::int64_t(m.log_time_ns)));
            return true;
          }
          if (t == o.camera_info) {
            msg::CameraInfo info = in.decode<msg::CameraInfo>(m);
            const std::int64_t stamp = ns_of(info.header.stamp);
            if (infos.empty() || infos.back().second.k != info.k || infos.back().second.width != info.width ||
                infos.back().second.height != info.height || infos.back().second.d != info.d)
              infos.emplace_back(stamp, std::move(info));
            return true;
          }
          for (int k = 0; k < kKinds; ++k) {
            if (t != topic[k]) continue;
            ImageHeader h = peek_image(m, in);
            check_encoding(Kind(k), h, std::int64_t(m.log_time_ns));
            if (!headers[k].empty() && h.stamp_ns <= headers[k].back().stamp_ns)
              refuse(t + ": header stamps do not increase (" + seconds(h.stamp_ns) + " after " +
                     seconds(headers[k].back().stamp_ns) + ")");
            if (k == kDepth && !headers[k].empty() && h.frame_id != headers[k].front().frame_id)
              refuse(t + ": the depth images name two frames, '" + headers[k].front().frame_id + "' and '" + h.frame_id +
                     "'");
            if (h.compressed && h.width == 0)
              refuse(t + " at " + seconds(h.stamp_ns) + ": a CompressedImage whose PNG header cannot be read");
            headers[k].push_back(std::move(h));
          }
          return true;
        },
        only);
    if (headers[kDepth].empty()) refuse(o.depth + ": no messages");
    if (headers[kRgb].empty()) refuse(o.rgb + ": no messages");
    if (o.label_images && headers[kLabels].empty()) refuse(o.labels + ": no messages");
    if (infos.empty()) refuse(o.camera_info + ": no messages");

    // Frames.
    const std::string& depth_frame = headers[kDepth].front().frame_id;
    if (o.frame.empty()) {
      o.frame = depth_frame;
    } else if (o.frame != depth_frame) {
      refuse("--frame " + o.frame + ": the depth images are in '" + depth_frame +
             "' (their header.frame_id, the optical frame the points are in); another frame would map every point "
             "moved");
    }
    if (!tf.has_frame(o.frame))
      refuse("the camera frame '" + o.frame + "' is in neither /tf nor /tf_static (frames there: " + list(tf.frames()) + ")");
    if (o.world_frame.empty()) {
      o.world_frame = tf.root_of(o.frame);
      choices.push_back("--world-frame " + o.world_frame + " (the root of the camera's transform tree)");
    } else if (!tf.has_frame(o.world_frame)) {
      refuse("--world-frame " + o.world_frame + ": in neither /tf nor /tf_static (frames there: " + list(tf.frames()) + ")");
    }
    if (tf.root_of(o.world_frame) != tf.root_of(o.frame))
      refuse("no transform between '" + o.world_frame + "' and '" + o.frame + "': a transform between the trees is missing");

    // Intrinsics: each camera_info, checked (the valid range is not in camera_info: the options').
    std::vector<CameraIntrinsics> cameras;
    for (const auto& [stamp, info] : infos) {
      CameraIntrinsics K;
      K.width_px = static_cast<int>(std::min<std::uint32_t>(info.width, 1u << 20));
      K.height_px = static_cast<int>(std::min<std::uint32_t>(info.height, 1u << 20));
      K.fx_px = info.k[0];
      K.fy_px = info.k[4];
      K.cx_px = info.k[2] + 0.5;  // ROS puts pixel centres at integer coordinates, canopy at +0.5
      K.cy_px = info.k[5] + 0.5;
      K.min_range_m = o.min_range_m;
      K.max_range_m = o.max_range_m;
      validate_params(K, in.path() + ": " + o.camera_info + " at " + seconds(stamp));
      cameras.push_back(K);
      if (std::any_of(info.d.begin(), info.d.end(), [](double d) { return d != 0.0; }) && notes.empty())
        notes.push_back(o.camera_info + " has a distortion (" + info.distortion_model +
                        "): the images are taken as rectified and it is ignored");
    }
    const auto camera_at = [&](std::int64_t stamp) -> const CameraIntrinsics& {
      std::size_t best = 0;
      for (std::size_t i = 1; i < infos.size(); ++i)
        if (std::llabs(infos[i].first - stamp) < std::llabs(infos[best].first - stamp)) best = i;
      return cameras[best];
    };
    for (int k = 0; k < kKinds; ++k)
      for (const ImageHeader& h : headers[k]) {
        const CameraIntrinsics& K = camera_at(h.stamp_ns);
        if (h.width != K.width_px || h.height != K.height_px)
          refuse(topic[k] + " at " + seconds(h.stamp_ns) + ": an image of " + std::to_string(h.width) + " x " +
                 std::to_string(h.height) + " beside a camera_info of " + std::to_string(K.width_px) + " x " +
                 std::to_string(K.height_px) + " (images must be registered to the colour camera)");
      }

    // Pairing: each depth image with the nearest colour (and label) image within max_dt, and its pose.
    const std::int64_t tolerance = std::llround(o.max_dt_s * 1e9);
    const auto nearest = [&](Kind k, std::int64_t stamp, std::int64_t* gap) -> std::optional<std::uint32_t> {
      const std::vector<ImageHeader>& h = headers[k];
      const auto it = std::lower_bound(h.begin(), h.end(), stamp,
                                       [](const ImageHeader& a, std::int64_t x) { return a.stamp_ns < x; });
      std::optional<std::uint32_t> best;
      *gap = std::numeric_limits<std::int64_t>::max();
      for (auto c : {it, it == h.begin() ? h.end() : it - 1})
        if (c != h.end() && std::llabs(c->stamp_ns - stamp) < *gap) {
          *gap = std::llabs(c->stamp_ns - stamp);
          best = static_cast<std::uint32_t>(c - h.begin());
        }
      if (*gap > tolerance) return std::nullopt;
      return best;
    };
    for (std::size_t i = 0; i < headers[kDepth].size(); ++i) {
      const std::int64_t stamp = headers[kDepth][i].stamp_ns;
      PlannedFrame f;
      f.name = seconds(stamp).substr(0, seconds(stamp).size() - 2);
      f.part[kDepth] = static_cast<std::uint32_t>(i);
      std::string why;
      bool ok = true;
      for (Kind k : {kRgb, kLabels}) {
        if (topic[k].empty() || !ok) continue;
        std::int64_t gap = 0;
        const std::optional<std::uint32_t> j = nearest(k, stamp, &gap);
        if (!j) {
          why = std::string("no ") + (k == kRgb ? "colour" : "label") + " image within max_dt (the nearest is " +
                seconds(gap) + " away)";
          ok = false;
        } else {
          f.part[k] = *j;
        }
      }
      if (ok) {
        const std::optional<Pose> T = tf.lookup(o.world_frame, o.frame, stamp, tolerance, &why);
        if (T) f.T_world_camera = *T;
        else ok = false;
      }
      if (!ok) {
        skipped.push_back({f.name, why});
        continue;
      }
      f.intrinsics = camera_at(stamp);
      for (int k = 0; k < kKinds; ++k)
        if (!topic[k].empty()) ++uses[k][f.part[k]];
      frames.push_back(std::move(f));
    }
  }

  // The second pass, on `reader`: every image topic in log-time order; a frame is handed over
  // once its messages are all read, in order, at most two waiting.
  void second_pass() {
    try {
      ros2::McapReadOptions only;
      for (int k = 0; k < kKinds; ++k)
        if (!topic[k].empty()) only.topics.push_back(topic[k]);
      std::uint32_t ordinal[kKinds] = {0, 0, 0};
      std::map<std::pair<int, std::uint32_t>, std::shared_ptr<const std::string>> held;
      std::uint64_t held_bytes = 0;
      std::size_t next = 0;
      in.for_each_message(
          [&](const ros2::McapMessage& m) {
            for (int k = 0; k < kKinds; ++k) {
              if (m.channel->topic != topic[k]) continue;
              const std::uint32_t ord = ordinal[k]++;
              if (!uses[k].count(ord)) continue;
              held[{k, ord}] = std::make_shared<const std::string>(m.data);
              held_bytes += m.data.size();
            }
            if (held_bytes > o.max_held_bytes)
              throw InputError(in.path() + ": a frame's images lie more than " + std::to_string(o.max_held_bytes >> 20) +
                               " MiB of images apart; canopy does not hold them");
            while (next < frames.size()) {
              const PlannedFrame& f = frames[next];
              FrameBytes b;
              bool complete = true;
              for (int k = 0; k < kKinds && complete; ++k) {
                if (topic[k].empty()) continue;
                const auto it = held.find({k, f.part[k]});
                if (it == held.end()) complete = false;
                else b.part[k] = it->second;
              }
              if (!complete) break;
              for (int k = 0; k < kKinds; ++k)
                if (!topic[k].empty() && --uses[k][f.part[k]] == 0) {
                  held_bytes -= b.part[k]->size();
                  held.erase({k, f.part[k]});
                }
              std::unique_lock<std::mutex> lock(mutex);
              changed.wait(lock, [&] { return cancel || ready.size() < 2; });
              if (cancel) return false;
              ready.push_back(std::move(b));
              ++next;
              changed.notify_all();
            }
            std::lock_guard<std::mutex> lock(mutex);
            return !cancel;
          },
          only);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
    }
    changed.notify_all();
  }

  bool read(std::size_t i, LabelledFrame* out, std::string* why) {
    CANOPY_CHECK(i == delivered, "McapFrames: frame " << i << " read out of order (next " << delivered << ")");
    if (!reader.joinable()) reader = std::thread([this] { second_pass(); });
    FrameBytes b;
    {
      std::unique_lock<std::mutex> lock(mutex);
      changed.wait(lock, [&] { return !ready.empty() || done; });
      if (ready.empty()) {
        if (error) std::rethrow_exception(error);
        throw InputError(in.path() + ": the recording ended before frame " + frames[i].name + "'s images");
      }
      b = std::move(ready.front());
      ready.pop_front();
    }
    changed.notify_all();
    ++delivered;
    const PlannedFrame& f = frames[i];
    out->intrinsics = f.intrinsics;
    out->T_world_camera = f.T_world_camera;
    decode_depth(*b.part[kDepth], f, out);
    decode_rgb(*b.part[kRgb], f, out);
    if (b.part[kLabels]) decode_labels(*b.part[kLabels], f, out);
    (void)why;
    return true;
  }

  // An Image's pixel rows checked against its size; throws naming the topic and frame.
  const std::uint8_t* rows(const msg::Image& im, int bytes_per_pixel, Kind k, const PlannedFrame& f) const {
    const std::uint64_t row = std::uint64_t(im.width) * std::uint64_t(bytes_per_pixel);
    if (im.is_bigendian && bytes_per_pixel > 1) refuse(topic[k] + " at " + f.name + " s: a big-endian image");
    if (im.step < row || std::uint64_t(im.step) * im.height > im.data.size())
      refuse(topic[k] + " at " + f.name + " s: an image of " + std::to_string(im.width) + " x " +
             std::to_string(im.height) + " " + im.encoding + " with step " + std::to_string(im.step) + " and " +
             std::to_string(im.data.size()) + " bytes");
    return im.data.data();
  }

  template <class M>
  M decode_message(const std::string& bytes, Kind k, const PlannedFrame& f) const {
    try {
      return ros2::deserialize<M>(bytes);
    } catch (const InputError& e) {
      refuse(topic[k] + " at " + f.name + " s: " + e.what());
    }
  }

  void decode_depth(const std::string& bytes, const PlannedFrame& f, LabelledFrame* out) const {
    const msg::Image im = decode_message<msg::Image>(bytes, kDepth, f);
    const bool metres = im.encoding == "32FC1";
    const std::uint8_t* p = rows(im, metres ? 4 : 2, kDepth, f);
    out->depth_m = Image<float>(static_cast<int>(im.width), static_cast<int>(im.height), 0.0f);
    for (std::uint32_t y = 0; y < im.height; ++y)
      for (std::uint32_t x = 0; x < im.width; ++x) {
        const std::uint8_t* px = p + std::size_t(y) * im.step + std::size_t(x) * (metres ? 4 : 2);
        float z = 0.0f;
        if (metres) {
          std::memcpy(&z, px, 4);
          if (!(std::isfinite(z) && z > 0.0f)) z = 0.0f;  // REP 118: NaN, inf: no return
        } else {
          std::uint16_t mm = 0;
          std::memcpy(&mm, px, 2);
          z = static_cast<float>(mm / 1000.0);  // 0: no return
        }
        out->depth_m.at(int(x), int(y)) = z;
      }
  }

  void decode_rgb(const std::string& bytes, const PlannedFrame& f, LabelledFrame* out) const {
    if (compressed_rgb) {
      const msg::CompressedImage c = decode_message<msg::CompressedImage>(bytes, kRgb, f);
      out->rgb = decode_png_rgb(std::string_view(reinterpret_cast<const char*>(c.data.data()), c.data.size()),
                                in.path() + ": " + topic[kRgb] + " at " + f.name + " s");
      if (out->rgb.width != f.intrinsics.width_px || out->rgb.height != f.intrinsics.height_px)
        refuse(topic[kRgb] + " at " + f.name + " s: a PNG of another size than camera_info's");
      return;
    }
    const msg::Image im = decode_message<msg::Image>(bytes, kRgb, f);
    const int n = im.encoding == "rgba8" || im.encoding == "bgra8" ? 4 : 3;
    const bool bgr = im.encoding[0] == 'b';
    const std::uint8_t* p = rows(im, n, kRgb, f);
    out->rgb = Image<Rgb8>(static_cast<int>(im.width), static_cast<int>(im.height));
    for (std::uint32_t y = 0; y < im.height; ++y)
      for (std::uint32_t x = 0; x < im.width; ++x) {
        const std::uint8_t* px = p + std::size_t(y) * im.step + std::size_t(x) * n;
        out->rgb.at(int(x), int(y)) = bgr ? Rgb8{px[2], px[1], px[0]} : Rgb8{px[0], px[1], px[2]};
      }
  }

  void decode_labels(const std::string& bytes, const PlannedFrame& f, LabelledFrame* out) const {
    const msg::Image im = decode_message<msg::Image>(bytes, kLabels, f);
    const std::uint8_t* p = rows(im, 1, kLabels, f);
    out->class_id = Image<std::uint8_t>(static_cast<int>(im.width), static_cast<int>(im.height));
    for (std::uint32_t y = 0; y < im.height; ++y)
      std::memcpy(&out->class_id.at(0, int(y)), p + std::size_t(y) * im.step, im.width);
  }
};

McapFrames::McapFrames(const std::string& path, const McapFrameOptions& options)
    : impl_(std::make_unique<Impl>(path, options)) {
  if (!(std::isfinite(options.max_dt_s) && options.max_dt_s > 0.0 && options.max_dt_s <= 10.0))
    throw InputError("--max-dt: " + std::to_string(options.max_dt_s) + " s is not in (0, 10]");
  impl_->choose_topics();
  impl_->first_pass();
}

McapFrames::~McapFrames() = default;

const std::vector<std::string>& McapFrames::choices() const { return impl_->choices; }
const McapFrameOptions& McapFrames::options() const { return impl_->o; }

RecordedSequence McapFrames::sequence() {
  Impl& s = *impl_;
  RecordedSequence seq;
  seq.source = s.in.path();
  seq.classes = s.o.classes;
  seq.size = s.frames.size();
  seq.name = [&s](std::size_t i) { return s.frames[i].name; };
  seq.read = [&s](std::size_t i, LabelledFrame* f, std::string* why) { return s.read(i, f, why); };
  seq.skipped = s.skipped;
  seq.notes = s.notes;
  const McapFrameOptions& used = s.o;
  seq.run["command"] = "map";
  seq.run["mcap"] = s.in.path();
  seq.run["topics"]["rgb"] = used.rgb;
  seq.run["topics"]["depth"] = used.depth;
  seq.run["topics"]["camera_info"] = used.camera_info;
  if (used.label_images) seq.run["topics"]["labels"] = used.labels;
  seq.run["frame"] = used.frame;
  seq.run["world_frame"] = used.world_frame;
  seq.run["labels"] = used.label_images ? "label images" : "color";
  seq.run["classes"] = seq.classes.names;
  seq.run["max_time_diff_s"] = used.max_dt_s;
  seq.run["range_m"] = std::vector<double>{used.min_range_m, used.max_range_m};
  return seq;
}

}  // namespace canopy::jobs
