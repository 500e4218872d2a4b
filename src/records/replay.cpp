// A run's record for its report (replay.h).

#include "canopy/records/replay.h"

#include <algorithm>
#include <cmath>

#include "canopy/mapping/voxel_key.h"

namespace canopy::records {

std::uint16_t drawn_state(const mapping::SemanticOcTree& map, const mapping::SemanticState* s) {
  if (!s || s->occupancy_logodds() <= 0.f) return 0;
  const int c = std::clamp(s->most_likely_class(), 0, 63);
  const int occ = std::clamp(static_cast<int>((s->occupancy() - 0.5) / 0.5 * 4.0), 0, 3);
  const double top = std::max(map.unseen_entropy(), 1e-9);
  const int ent = std::clamp(static_cast<int>(map.entropy_of(*s) / top * 8.0), 0, 7);
  return static_cast<std::uint16_t>(0x8000 | c | occ << 6 | ent << 8);
}

MapReplay::MapReplay(SemanticClasses classes, int thumb_width_px)
    : classes_(std::move(classes)), thumb_width_px_(std::max(8, thumb_width_px)) {}

void MapReplay::record_scan(const mapping::SemanticOcTree& map, const std::vector<mapping::VoxelUpdate>& updates,
                            const std::vector<std::uint8_t>* occupancy) {
  constexpr std::uint8_t kEither = mapping::SemanticOcTree::kOccupiedBefore | mapping::SemanticOcTree::kOccupiedAfter;
  if (occupancy && occupancy->size() != updates.size()) occupancy = nullptr;
  const Stopwatch watch;
  std::vector<VoxelChange> changes;
  std::lock_guard<std::mutex> lock(scan_mutex_);
  for (std::size_t i = 0; i < updates.size(); ++i) {
    // Free before and after: not drawn either time (most of a scan's pass-throughs).
    if (occupancy && !((*occupancy)[i] & kEither)) continue;
    const mapping::VoxelUpdate& u = updates[i];
    const octomap::OcTreeKey key = mapping::morton_key(u.code);
    const std::uint16_t state = drawn_state(map, map.find(key));
    auto it = last_.find(u.code);
    if (it == last_.end()) {
      if (state == 0) continue;  // never drawn: not worth an index
      it = last_.emplace(u.code, std::make_pair(static_cast<std::uint32_t>(voxels_.size()), std::uint16_t(0))).first;
      voxels_.push_back(key);
    }
    if (it->second.second == state) continue;
    it->second.second = state;
    changes.push_back({it->second.first, state});
  }
  std::sort(changes.begin(), changes.end(), [](const VoxelChange& a, const VoxelChange& b) { return a.voxel < b.voxel; });
  scans_.push_back(std::move(changes));
  scan_seconds_ += watch.seconds();
}

std::optional<std::vector<double>> MapReplay::fruit_coverage_after(std::size_t scan) const {
  std::lock_guard<std::mutex> lock(scan_mutex_);
  if (scan >= fruits_.size()) return std::nullopt;
  return fruits_[scan];
}

void MapReplay::record_fruits(const evaluation::MapMetrics& metrics) {
  std::vector<double> c;
  c.reserve(metrics.fruits.size());
  for (const evaluation::FruitMetrics& f : metrics.fruits) c.push_back(f.coverage);
  std::lock_guard<std::mutex> lock(scan_mutex_);
  fruits_.push_back(std::move(c));
}

void MapReplay::record_frame(const LabelledFrame& frame, const Image<std::uint8_t>* mapped_labels) {
  const Stopwatch watch;
  const int w = thumb_width_px_;
  const int src_w = std::max(1, frame.rgb.width), src_h = std::max(1, frame.rgb.height);
  const int h = std::max(1, static_cast<int>(std::lround(double(w) * src_h / src_w)));
  const auto same_size = [&](const Image<std::uint8_t>& im) {
    return frame.rgb.width > 0 && im.width == frame.rgb.width && im.height == frame.rgb.height;
  };
  const bool mapped = mapped_labels && same_size(*mapped_labels);
  Image<Rgb8> rgb(w, h), labels(w, h), mapped_thumb(mapped ? w : 0, mapped ? h : 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {  // nearest pixel: labels keep their colours
      const int sx = std::min(src_w - 1, (2 * x + 1) * src_w / (2 * w));
      const int sy = std::min(src_h - 1, (2 * y + 1) * src_h / (2 * h));
      if (frame.rgb.width > 0) rgb.at(x, y) = frame.rgb.at(sx, sy);
      if (same_size(frame.class_id)) labels.at(x, y) = classes_.color(frame.class_id.at(sx, sy));
      if (mapped) mapped_thumb.at(x, y) = classes_.color(mapped_labels->at(sx, sy));
    }
  // The fruit instances seen: pixels of an instance that hold a depth.
  std::vector<int> seen;
  const bool with_depth = frame.depth_m.width == frame.instance.width && frame.depth_m.height == frame.instance.height;
  for (std::size_t i = 0; i < frame.instance.data.size(); ++i) {
    const int id = frame.instance.data[i];
    if (id == kNoInstance || (with_depth && !(frame.depth_m.data[i] > 0.f))) continue;
    if (seen.empty() || seen.back() != id) seen.push_back(id);  // runs of one id: most pixels skip here
  }
  std::sort(seen.begin(), seen.end());
  seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
  std::lock_guard<std::mutex> lock(frame_mutex_);
  seen_.push_back(std::move(seen));
  rgb_.push_back(std::move(rgb));
  labels_.push_back(std::move(labels));
  if (mapped) mapped_.push_back(std::move(mapped_thumb));
  frame_seconds_ += watch.seconds();
}

void MapReplay::record_robot(const std::vector<std::string>& links, const std::vector<std::string>& parents,
                             const std::vector<Pose>& T_world_link) {
  std::lock_guard<std::mutex> lock(frame_mutex_);
  if (robot_links_.empty()) {
    robot_links_ = links;
    robot_parents_ = parents;
  }
  robot_poses_.push_back(T_world_link);
}

double MapReplay::seconds() const {
  std::scoped_lock lock(scan_mutex_, frame_mutex_);
  return scan_seconds_ + frame_seconds_;
}

std::size_t MapReplay::change_count() const {
  std::lock_guard<std::mutex> lock(scan_mutex_);
  std::size_t n = 0;
  for (const auto& s : scans_) n += s.size();
  return n;
}

}  // namespace canopy::records
