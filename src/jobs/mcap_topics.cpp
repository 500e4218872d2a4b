#include "canopy/jobs/mcap_topics.h"

#include <algorithm>
#include <map>

#include "canopy/common/error.h"
#include "canopy/jobs/mcap_job.h"
#include "canopy/ros2/messages.h"

namespace canopy::jobs {

namespace {

namespace msg = ros2::msg;
namespace topics = recording_topics;

std::string topic_dirname(const std::string& topic) {
  const std::size_t slash = topic.rfind('/');
  return slash == std::string::npos || slash == 0 ? "" : topic.substr(0, slash);
}

std::string names_text(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s.empty() ? "none" : s;
}

void check_topic(const std::map<std::string, RecordingTopic>& all, const std::string& name, const char* flag,
                 const std::vector<std::string>& types) {
  const auto it = all.find(name);
  if (it == all.end()) {
    std::vector<std::string> names;
    for (const auto& [n, t] : all) names.push_back(n + " (" + t.type + ")");
    throw InputError(std::string(flag) + " " + name + ": no such topic (the recording has " + names_text(names) + ")");
  }
  if (std::find(types.begin(), types.end(), it->second.type) == types.end())
    throw InputError(std::string(flag) + " " + name + ": a topic of type " + it->second.type + ", not " +
                     names_text(types));
}

// The one candidate, or the one whose name has one of `words` as a path component or part.
std::string pick(std::vector<std::string> candidates, const std::vector<std::string>& words, const char* flag,
                 const char* what) {
  if (candidates.size() > 1) {
    std::vector<std::string> preferred;
    for (const std::string& c : candidates)
      for (const std::string& w : words)
        if (c.find(w) != std::string::npos) {
          preferred.push_back(c);
          break;
        }
    if (preferred.size() == 1) candidates = preferred;
  }
  if (candidates.size() == 1) return candidates.front();
  throw InputError(std::string(candidates.empty() ? "no " : "several ") + what + " topics (" + names_text(candidates) +
                   "): name one with " + flag);
}

}  // namespace

bool is_depth_encoding(const std::string& e) { return e == "16UC1" || e == "mono16" || e == "32FC1"; }
bool is_colour_encoding(const std::string& e) { return e == "rgb8" || e == "bgr8" || e == "rgba8" || e == "bgra8"; }
bool is_label_encoding(const std::string& e) { return e == "mono8" || e == "8UC1"; }
bool is_png(const std::string& format) { return format.find("png") != std::string::npos; }

bool choice_needs_encodings(const McapFrameOptions& o) {
  return o.depth.empty() || o.rgb.empty() || (o.label_images && o.labels.empty());
}

std::vector<std::string> choose_mcap_topics(const std::vector<RecordingTopic>& listed, McapFrameOptions& o) {
  std::map<std::string, RecordingTopic> all;
  for (const RecordingTopic& t : listed) all.emplace(t.name, t);
  std::vector<std::string> choices;
  const std::vector<std::string> image_types = {msg::Image::kTypeName, msg::CompressedImage::kTypeName};
  const auto has = [&](const char* t) { return all.count(t) > 0; };
  if (o.depth.empty()) {
    if (has(topics::kDepth)) {
      o.depth = topics::kDepth;
    } else {
      std::vector<std::string> c;
      for (const auto& [name, t] : all)
        if (t.type == msg::Image::kTypeName && is_depth_encoding(t.encoding)) c.push_back(name);
      o.depth = pick(c, {"aligned", "registered"}, "--depth", "depth image (16UC1, mono16, 32FC1)");
    }
    choices.push_back("--depth " + o.depth + " (chosen from the recording)");
  }
  if (o.rgb.empty()) {
    if (has(topics::kRgb)) {
      o.rgb = topics::kRgb;
    } else {
      std::vector<std::string> c;
      for (const auto& [name, t] : all) {
        const std::string& e = t.encoding;
        const bool compressed = t.type == msg::CompressedImage::kTypeName;
        if (name == topics::kLabelsColor || !(compressed || t.type == msg::Image::kTypeName)) continue;
        if (compressed ? (is_png(e) && e.find("epth") == std::string::npos) : is_colour_encoding(e)) c.push_back(name);
      }
      // image_transport's NAME/compressed beside NAME: the raw one.
      std::vector<std::string> raw;
      for (const std::string& name : c)
        if (!(name.size() > 11 && name.compare(name.size() - 11, 11, "/compressed") == 0 &&
              std::find(c.begin(), c.end(), name.substr(0, name.size() - 11)) != c.end()))
          raw.push_back(name);
      o.rgb = pick(raw, {"/color/", "/rgb/"}, "--rgb", "colour image (rgb8, bgr8, rgba8, bgra8, PNG)");
    }
    choices.push_back("--rgb " + o.rgb + " (chosen from the recording)");
  }
  if (o.label_images && o.labels.empty()) {
    if (!has(topics::kLabels))
      throw InputError("--seg truth reads label images: name their topic (mono8 class indices) with --labels");
    o.labels = topics::kLabels;
    choices.push_back("--labels " + o.labels + " (chosen from the recording)");
  }
  check_topic(all, o.depth, "--depth", {msg::Image::kTypeName});
  check_topic(all, o.rgb, "--rgb", image_types);
  if (o.label_images) check_topic(all, o.labels, "--labels", {msg::Image::kTypeName});
  if (o.camera_info.empty()) {
    std::vector<std::string> c;
    for (const auto& [name, t] : all)
      if (t.type == msg::CameraInfo::kTypeName) c.push_back(name);
    std::string chosen;
    for (const std::string& ns : {topic_dirname(o.rgb), topic_dirname(topic_dirname(o.rgb)), topic_dirname(o.depth)})
      if (chosen.empty() && !ns.empty() && all.count(ns + "/camera_info")) chosen = ns + "/camera_info";
    o.camera_info = chosen.empty() ? pick(c, {}, "--camera-info", "CameraInfo") : chosen;
    choices.push_back("--camera-info " + o.camera_info + " (chosen from the recording)");
  }
  check_topic(all, o.camera_info, "--camera-info", {msg::CameraInfo::kTypeName});
  return choices;
}

}  // namespace canopy::jobs
