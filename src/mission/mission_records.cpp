// The mission's records: view phases, the stop region, and why a mission's coverage is zero
// (mission.h).

#include <string>

#include "canopy/mission/mission.h"

namespace canopy::mission {

const char* to_string(ViewPhase p) {
  switch (p) {
    case ViewPhase::kInitial: return "initial";
    case ViewPhase::kNbv: return "nbv";
    case ViewPhase::kPredefined: return "predefined";
  }
  return "?";
}

Eigen::AlignedBox3d stop_region(const LoopParams& loop, double arm_x_m, double base_y_m) {
  return Eigen::AlignedBox3d(
      Vec3(arm_x_m - loop.region_half_length_m, base_y_m - loop.region_half_width_m, loop.region_min_z_m),
      Vec3(arm_x_m + loop.region_half_length_m, base_y_m + loop.region_half_width_m, loop.region_max_z_m));
}

int MissionResult::successful_views() const {
  int n = 0;
  for (const auto& v : views) n += v.success;
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

}  // namespace canopy::mission
