#pragma once
// Settings of the closed-loop mission (configs/mission.yaml): where the base stops, the
// predefined views of every stop (relative to the base), and when a stop's NBV loop ends.

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "canopy/common/types.h"
#include "canopy/common/yaml_reader.h"

namespace canopy::world {
struct WorldSpec;
}

namespace canopy::mission {

/// Base stops along the aisle.
struct StopParams {
  int count = 5;                       ///< Evenly spaced over the rows' plants when positions_m is empty.
  std::vector<double> positions_m;     ///< Arm-base x of each stop (world), overrides count.
  double base_y_m = 0.0;               ///< Base y at every stop (the aisle centre).
  double timeout_s = 30.0;             ///< Give up driving to a stop after this much simulated time.
};

/// The predefined views of a stop, built around target points relative to the arm base:
/// at every row (lateral offset) and height, one view per azimuth, looking from the aisle
/// side at `distance_m`, horizontally, with zero roll.
struct ScanParams {
  double distance_m = 0.4;                          ///< Camera distance to its target.
  std::vector<double> azimuths_deg = {-30.0, 0.0, 30.0};  ///< About world z, 0 = straight across the aisle.
  std::vector<double> heights_m = {0.55, 0.85};    ///< Target heights above the ground (initial scan).
  std::vector<double> extra_heights_m = {0.4, 1.0};  ///< Predefined scanning's additional views.
  std::vector<double> lateral_m;                   ///< Target |y| offsets with sign; empty: the world's rows.
  double along_m = 0.0;                            ///< Target x relative to the arm base.
};

/// The NBV loop of one stop.
struct LoopParams {
  int views_per_stop = 12;           ///< Successful NBV (or frontier) views wanted per stop.
  int max_rounds = 10;               ///< Planning rounds per stop at most.
  int max_attempts = 60;             ///< Attempted views per stop at most (after the initial scan).
  double region_half_length_m = 0.45;  ///< Targets within this of the arm base along x count.
  double region_half_width_m = 1.2;    ///< ... and within this laterally.
  double region_min_z_m = 0.05;
  double region_max_z_m = 1.8;
};

/// What the mission records beside the map.
struct RecordParams {
  double truth_voxel_m = 0.01;       ///< Voxel size of the ground-truth plant occupancy for contact counting.
  double base_check_period_s = 0.02; ///< Base-vs-plants checks while driving (simulated seconds).
  bool metrics_every_view = true;    ///< Coverage and entropy after every view (else only per stop).
};

/// All mission settings.
struct MissionParams {
  StopParams stops;
  ScanParams scan;
  LoopParams loop;
  RecordParams record;

  /// Reads the sections stops, scan, loop, record (every key optional, unknown keys rejected).
  static MissionParams from_yaml(YamlReader& y);
  YAML::Node to_yaml() const;
  bool operator==(const MissionParams& o) const;
};

/// Arm-base x of each stop in `world` (positions_m, or count evenly spaced over the plants;
/// one stop when the rows hold one plant each).
std::vector<double> stop_positions(const StopParams& params, const world::WorldSpec& world);

/// The predefined camera poses of a stop, in the base frame: the initial scan's
/// (heights_m) and, with `extra`, predefined scanning's additional ones (extra_heights_m).
/// `T_base_arm` places the arm base; rows come from `world` when lateral_m is empty.
std::vector<Pose> scan_views_in_base(const ScanParams& params, const world::WorldSpec& world, const Pose& T_base_arm,
                                     bool extra);

}  // namespace canopy::mission
