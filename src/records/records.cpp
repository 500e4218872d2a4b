// The mission's records (records.h): view phases, the per-view map figures, progress lines
// and captions, and why a mission's coverage is zero.

#include <cstdio>
#include <string>

#include "canopy/records/records.h"

#include "canopy/common/value_text.h"

namespace canopy::records {

const char* to_string(ViewPhase p) {
  switch (p) {
    case ViewPhase::kInitial: return "initial";
    case ViewPhase::kNbv: return "nbv";
    case ViewPhase::kPredefined: return "predefined";
  }
  return "?";
}

std::string zero_coverage_reason(const MissionResult& result, const std::string& target, perception::LabelSource labels) {
  if (result.final_metrics.coverage > 0.0) return "";
  long target_points = 0, true_pixels = 0;
  for (const auto& v : result.views) target_points += v.target_points, true_pixels += v.true_target_pixels;
  if (result.final_metrics.fruits.empty()) return "the world has no target fruit";
  if (result.successful_views() == 0) return "no view succeeded";
  return zero_coverage_cause(target, labels, target_points, true_pixels);
}

void set_map_metrics(const evaluation::MapMetrics& m, ViewRecord* rec) {
  rec->coverage = m.coverage;
  rec->entropy = m.total_entropy;
  rec->coverage_paper = m.paper.coverage;
  rec->entropy_paper = m.paper.entropy;
  rec->coverage_prototype = m.prototype.coverage;
  rec->entropy_prototype = m.prototype.entropy;
  rec->fruits_sc50 = m.fruits_sc50;
  rec->fruits_sc80 = m.fruits_sc80;
  rec->fruit_clusters = static_cast<int>(m.detection.clusters.size());
  rec->fruits_matched = static_cast<int>(m.detection.matches.size());
  rec->detection_precision = m.detection.precision;
  rec->detection_recall = m.detection.recall;
  rec->detection_f1 = m.detection.f1;
  rec->centre_error_m = m.detection.centre_error_m;
  rec->voxel_volume_error = m.detection.voxel_volume_error;
  rec->ellipsoid_volume_error = m.detection.ellipsoid_volume_error;
  rec->fruit_voxel_precision = m.voxel_precision.precision;
  rec->false_fruit_volume_m3 = m.voxel_precision.false_volume_m3;
}

std::string progress_line(const ViewRecord& v, int stops, double elapsed_s) {
  char b[200];
  c_snprintf(b, sizeof b, "stop %d/%d: %s view %d %s%s (views %d, SC %.3f, elapsed %.1f s)", v.stop + 1, stops,
                to_string(v.phase), v.attempt + 1, v.success ? "ok" : "failed: ", v.success ? "" : v.failure.c_str(),
                v.successful_views, v.coverage, elapsed_s);
  return v.success || v.message.empty() ? std::string(b) : std::string(b) + ": " + v.message;
}

std::string caption_line(const std::string& method, int stop, int stops, int views, double coverage) {
  char b[160];
  c_snprintf(b, sizeof b, "%s | stop %d/%d | views %d | fruit SC %.2f", method.c_str(), stop + 1, stops, views,
                coverage);
  return b;
}

void StopRecord::count(const ViewRecord& v) {
  if (v.phase == ViewPhase::kInitial) {
    ++initial_attempted;
    initial_ok += v.success;
    initial_target_points += v.target_points;
    initial_true_target_pixels += v.true_target_pixels;
  } else {
    ++nbv_attempted;
    nbv_ok += v.success;
  }
  if (!v.success) ++failures[v.failure];
}

int MissionResult::successful_views() const {
  int n = 0;
  for (const auto& v : views) n += v.success;
  return n;
}

int MissionResult::stops_not_reached() const {
  int n = 0;
  for (const StopRecord& s : stops) n += s.end == "base_failed";
  return n;
}

std::string zero_coverage_cause(const std::string& target, perception::LabelSource labels, long target_points,
                                long true_target_pixels) {
  const std::string t = "'" + target + "'";
  if (true_target_pixels == 0)
    return "no view saw a " + t + " pixel (the renderer's true labels show none in any frame): the views miss the fruit";
  if (target_points == 0) {
    std::string why = "the views saw " + std::to_string(true_target_pixels) + " " + t +
                      " pixels (the renderer's true labels) but the segmentation (labels: " + perception::to_string(labels) +
                      ") labelled none " + t;
    if (labels == perception::LabelSource::kColor)
      why += ": the fruit's rendered colours fall outside the colour bands (imported plants: check their colours with "
             "canopy world; --seg truth maps with the renderer's labels)";
    return why;
  }
  return std::to_string(target_points) + " points were labelled " + t + " but none was kept on a target fruit's surface";
}

}  // namespace canopy::records
