// The mission's records (records.h): view phases, the per-view map figures, progress lines
// and captions, and why a mission's coverage is zero.

#include <cstdio>
#include <string>

#include "canopy/records/records.h"

#include "canopy/common/value_text.h"

namespace canopy::records {

const char* to_string(ViewPhase phase) { return enum_name(kViewPhaseNames, phase); }
const char* to_string(FailureCause cause) { return enum_name(kFailureCauseNames, cause); }
const char* to_string(WallPhase phase) { return enum_name(kWallPhaseNames, phase); }
const char* to_string(PlotCategory category) { return enum_name(kPlotCategoryNames, category); }

const std::vector<PlotCategoryInfo>& plot_categories() {
  using W = WallPhase;
  static const std::vector<PlotCategoryInfo> table = {
      {PlotCategory::kMapping, "mapping", {W::kMapping}, true},
      {PlotCategory::kNbvPlanning, "NBV planning", {W::kClustering, W::kCandidates, W::kFiltering, W::kScoring, W::kNbvPlanning}, true},
      {PlotCategory::kMotionPlanning, "motion planning", {W::kMotionPlanning}, true},
      {PlotCategory::kControl, "control", {W::kControl}, true},
      {PlotCategory::kRendering, "rendering", {W::kRendering, W::kScene}, false},
      {PlotCategory::kEvaluation, "evaluation", {W::kEvaluation}, false},
  };
  return table;
}

namespace {
// How each phase's cameras are drawn, and the legend's words for them.
struct ViewPhaseStyle {
  ViewPhase phase;
  Rgb8 colour;
  const char* legend;
};
constexpr ViewPhaseStyle kViewPhaseStyles[] = {
    {ViewPhase::kInitial, {0x8e, 0x44, 0xad}, "initial scan"},
    {ViewPhase::kNbv, {0x1f, 0x77, 0xb4}, "next-best view"},
    {ViewPhase::kPredefined, {0x17, 0xbe, 0xcf}, "predefined"},
    {ViewPhase::kMapView, {0x1f, 0x77, 0xb4}, "view"},
};
constexpr Rgb8 kFailedViewColour{0xe3, 0x77, 0xc2};

const ViewPhaseStyle& style_of(ViewPhase phase) {
  for (const ViewPhaseStyle& s : kViewPhaseStyles)
    if (s.phase == phase) return s;
  return kViewPhaseStyles[0];
}

std::string hex(const Rgb8& c) {
  char b[8];
  c_snprintf(b, sizeof b, "#%02x%02x%02x", c.r, c.g, c.b);
  return b;
}
}  // namespace

Rgb8 view_colour(ViewPhase phase, bool success) { return success ? style_of(phase).colour : kFailedViewColour; }
const char* view_phase_legend(ViewPhase phase) { return style_of(phase).legend; }

nlohmann::json vocabulary_json() {
  nlohmann::json phases = nlohmann::json::array(), causes = nlohmann::json::array(), walls = nlohmann::json::array(),
                 categories = nlohmann::json::array();
  for (const auto& p : kViewPhaseNames)
    phases.push_back({{"name", p.name}, {"colour", hex(view_colour(p.value, true))}, {"legend", view_phase_legend(p.value)}});
  for (const auto& c : kFailureCauseNames)
    if (c.value != FailureCause::kNone) causes.push_back(c.name);
  for (const auto& w : kWallPhaseNames) walls.push_back(w.name);
  for (const PlotCategoryInfo& c : plot_categories()) {
    nlohmann::json sums = nlohmann::json::array();
    for (const WallPhase w : c.phases) sums.push_back(to_string(w));
    categories.push_back({{"name", to_string(c.category)}, {"title", c.title}, {"phases", sums}, {"paper", c.paper}});
  }
  return {{"view_phases", phases},
          {"failed_view_colour", hex(kFailedViewColour)},
          {"failure_causes", causes},
          {"wall_phases", walls},
          {"plot_categories", categories}};
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
                to_string(v.phase), v.attempt + 1, v.success ? "ok" : "failed: ", v.success ? "" : to_string(v.failure),
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
  if (!v.success) ++failures[to_string(v.failure)];
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
