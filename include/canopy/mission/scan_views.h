#pragma once
// The mission's scan geometry: where the base stops along the aisle and the predefined views
// of each stop (the initial scan, predefined scanning's extra views and the replacements of a
// failed one), from the bundle's mission settings (settings/mission_params.h).

#include <vector>

#include "canopy/common/types.h"
#include "canopy/settings/mission_params.h"

namespace canopy::world {
struct WorldSpec;
}

namespace canopy::mission {

/// Arm-base x of each stop in `world` (positions_m, or count evenly spaced over the plants;
/// one stop when the rows hold one plant each).
std::vector<double> stop_positions(const settings::StopParams& params, const world::WorldSpec& world);

/// The predefined camera poses of a stop, in the base frame: the initial scan's
/// (heights_m) and, with `extra`, predefined scanning's additional ones (extra_heights_m).
/// `T_base_arm` places the arm base; rows come from `world` when lateral_m is empty.
std::vector<Pose> scan_views_in_base(const settings::ScanParams& params, const world::WorldSpec& world, const Pose& T_base_arm,
                                     bool extra);

/// One view of the scan pattern: the target at (along_m, lateral_m, height_m) from the arm
/// base (height above the ground), the camera distance_m from it on the aisle side, turned
/// by azimuth_deg about z, looking horizontally with zero roll.
struct ScanView {
  Pose T_base_camera = Pose::Identity();
  double lateral_m = 0.0, height_m = 0.0, azimuth_deg = 0.0;
};

/// The pattern's view at (lateral, height, azimuth), in the base frame.
ScanView scan_view(const settings::ScanParams& params, const Pose& T_base_arm, double lateral_m, double height_m,
                   double azimuth_deg);
/// The stop's scripted views with their pattern coordinates (the same views, in the same
/// order, as scan_views_in_base).
std::vector<ScanView> scan_view_list(const settings::ScanParams& params, const world::WorldSpec& world, const Pose& T_base_arm,
                                     bool extra);
/// Predefined scanning's replacements of a failed scripted view: the pattern's views on the
/// grid of replace_height_step_m x replace_azimuth_step_deg around it (replace_steps each
/// way, same row and distance, azimuths inside (-90, 90) deg, heights > 0), nearest first by
/// camera displacement plus distance_m times the rotation angle; the failed view itself is
/// left out. Ties keep grid order, so the list is deterministic.
std::vector<ScanView> scan_replacements(const settings::ScanParams& params, const Pose& T_base_arm, const ScanView& failed);

}  // namespace canopy::mission
