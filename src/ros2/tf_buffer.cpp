#include "canopy/ros2/tf_buffer.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "canopy/common/error.h"

namespace canopy::ros2 {

namespace {
std::string seconds_text(std::int64_t ns) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.9f s", static_cast<double>(ns) / 1e9);
  return buf;
}
std::int64_t stamp_of(const msg::Time& t) {
  return static_cast<std::int64_t>(t.sec) * 1000000000 + static_cast<std::int64_t>(t.nanosec);
}
}  // namespace

void TfBuffer::add(const msg::TFMessage& message, bool is_static, const std::string& where) {
  for (const msg::TransformStamped& t : message.transforms) {
    const std::string& parent = t.header.frame_id;
    const std::string& child = t.child_frame_id;
    if (parent == child || child.empty())
      throw InputError(where + ": a transform from '" + parent + "' to '" + child + "' (a frame to itself or unnamed)");
    const msg::Quaternion& q = t.transform.rotation;
    const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(std::abs(norm - 1.0) <= 1e-3))
      throw InputError(where + ": the transform " + parent + " -> " + child +
                       " is not rigid (its quaternion's norm is " + std::to_string(norm) + ", not 1)");
    const msg::Vector3& v = t.transform.translation;
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw InputError(where + ": the transform " + parent + " -> " + child + " has a translation that is not finite");
    auto [it, fresh] = edges_.try_emplace(child);
    Edge& e = it->second;
    if (fresh) {
      e.parent = parent;
      e.is_static = is_static;
    } else if (e.parent != parent) {
      throw InputError(where + ": the frame '" + child + "' has two parents, '" + e.parent + "' and '" + parent + "'");
    }
    Sample s;
    s.stamp_ns = stamp_of(t.header.stamp);
    s.translation = Vec3(v.x, v.y, v.z);
    s.rotation = Eigen::Quaterniond(q.w / norm, q.x / norm, q.y / norm, q.z / norm);
    if (is_static || e.is_static) {  // a static edge holds its latest value at all times
      e.is_static = true;
      e.samples.assign(1, s);
      continue;
    }
    if (!e.samples.empty() && s.stamp_ns < e.samples.back().stamp_ns) e.sorted = false;
    e.samples.push_back(s);
  }
}

bool TfBuffer::has_frame(const std::string& frame) const {
  if (edges_.count(frame)) return true;
  for (const auto& [child, e] : edges_)
    if (e.parent == frame) return true;
  return false;
}

std::string TfBuffer::root_of(const std::string& frame) const {
  std::string f = frame;
  for (std::size_t steps = 0; steps <= edges_.size(); ++steps) {
    const auto it = edges_.find(f);
    if (it == edges_.end()) return f;
    f = it->second.parent;
  }
  throw InputError("the transforms above '" + frame + "' form a loop");
}

std::vector<std::string> TfBuffer::frames() const {
  std::set<std::string> all;
  for (const auto& [child, e] : edges_) {
    all.insert(child);
    all.insert(e.parent);
  }
  return {all.begin(), all.end()};
}

std::optional<Pose> TfBuffer::edge_at(const std::string& child, const Edge& e, std::int64_t t, std::int64_t tolerance,
                                      std::string* why) const {
  const auto pose = [](const Vec3& p, const Eigen::Quaterniond& q) {
    Pose T = Pose::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = p;
    return T;
  };
  if (!e.sorted) {
    std::stable_sort(e.samples.begin(), e.samples.end(),
                     [](const Sample& a, const Sample& b) { return a.stamp_ns < b.stamp_ns; });
    e.sorted = true;
  }
  const std::vector<Sample>& s = e.samples;
  if (e.is_static) return pose(s.front().translation, s.front().rotation);
  const auto after = std::lower_bound(s.begin(), s.end(), t, [](const Sample& a, std::int64_t x) { return a.stamp_ns < x; });
  if (after != s.end() && after->stamp_ns == t) return pose(after->translation, after->rotation);
  if (after == s.begin() || after == s.end()) {
    const Sample& end = after == s.begin() ? s.front() : s.back();
    if (std::llabs(end.stamp_ns - t) <= tolerance) return pose(end.translation, end.rotation);
    if (why)
      *why = "the transform " + e.parent + " -> " + child + " has no sample within max_dt of " + seconds_text(t) +
             " (its samples run from " + seconds_text(s.front().stamp_ns) + " to " + seconds_text(s.back().stamp_ns) + ")";
    return std::nullopt;
  }
  const Sample& a = *(after - 1);
  const Sample& b = *after;
  const double w = static_cast<double>(t - a.stamp_ns) / static_cast<double>(b.stamp_ns - a.stamp_ns);
  return pose(a.translation + w * (b.translation - a.translation), a.rotation.slerp(w, b.rotation));
}

std::optional<Pose> TfBuffer::root_pose(const std::string& frame, std::int64_t t, std::int64_t tolerance,
                                        std::string* why) const {
  Pose T = Pose::Identity();
  std::string f = frame;
  for (std::size_t steps = 0; steps <= edges_.size(); ++steps) {
    const auto it = edges_.find(f);
    if (it == edges_.end()) return T;
    const std::optional<Pose> edge = edge_at(f, it->second, t, tolerance, why);
    if (!edge) return std::nullopt;
    T = *edge * T;
    f = it->second.parent;
  }
  throw InputError("the transforms above '" + frame + "' form a loop");
}

std::optional<Pose> TfBuffer::lookup(const std::string& target, const std::string& source, std::int64_t stamp_ns,
                                     std::int64_t tolerance_ns, std::string* why) const {
  const std::string root = root_of(source);
  if (root_of(target) != root) {
    if (why)
      *why = "no transform between '" + target + "' (tree of '" + root_of(target) + "') and '" + source +
             "' (tree of '" + root + "'): a transform between the trees is missing";
    return std::nullopt;
  }
  const std::optional<Pose> T_root_source = root_pose(source, stamp_ns, tolerance_ns, why);
  if (!T_root_source) return std::nullopt;
  if (target == root) return T_root_source;
  const std::optional<Pose> T_root_target = root_pose(target, stamp_ns, tolerance_ns, why);
  if (!T_root_target) return std::nullopt;
  return Pose(T_root_target->inverse() * *T_root_source);
}

}  // namespace canopy::ros2
