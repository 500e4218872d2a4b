#pragma once
// Settings of the closed-loop mission (configs/mission.yaml), the bundle's `mission` section:
// where the base stops, the predefined views of every stop (relative to the base), when a
// stop's NBV loop ends, what is recorded, and the oracle planners' settings. The controller
// (mission/mission.h) and its scan geometry (mission/scan_views.h) read them.

#include <string>
#include <vector>

#include "canopy/common/types.h"
#include "canopy/common/params.h"

namespace canopy::settings {

/// Base stops along the aisle.
struct StopParams {
  int count = 5;
  std::vector<double> positions_m;
  double base_y_m = 0.0;
  double timeout_s = 30.0;
  std::string arm_on_drive = "clear";

  template <class A>
  void visit(A& a) {
    a("count", count, limits::in(1, 1000), "Stops evenly spaced over the rows' plants (when positions_m is empty)");
    a("positions_m", positions_m, limits::finite(), "Arm-base x of each stop in the world; overrides count [m]");
    a("base_y_m", base_y_m, limits::finite(), "Base y at every stop (the aisle centre) [m]");
    a("timeout_s", timeout_s, limits::positive(), "Give up driving to a stop after this much simulated time beyond the straight drive's least time at the base's top speed [s]");
    a.one_of("arm_on_drive", arm_on_drive, {"hold", "clear", "always"},
             "The arm while the base drives to the next stop: 'hold' keeps the last view's configuration; 'clear' "
             "first moves it to the robot's home configuration (planned against the map) when, held, it would pass "
             "through the map's occupied voxels on the straight drive; 'always' before every drive");
  }
};

/// The predefined views of a stop, built around target points relative to the arm base:
/// at every row (lateral offset) and height, one view per azimuth, looking from the aisle
/// side at `distance_m`, horizontally, with zero roll.
struct ScanParams {
  double distance_m = 0.4;
  std::vector<double> azimuths_deg = {-30.0, 0.0, 30.0};
  std::vector<double> heights_m = {0.55, 0.85};
  std::vector<double> extra_heights_m = {0.4, 1.0};
  std::vector<double> lateral_m;
  double along_m = 0.0;
  bool replace_failed = true;
  double replace_height_step_m = 0.05;
  double replace_azimuth_step_deg = 10.0;
  int replace_steps = 4;
  int replace_max_attempts = 4;

  template <class A>
  void visit(A& a) {
    a("distance_m", distance_m, limits::positive(), "Camera distance to its target [m]");
    a("azimuths_deg", azimuths_deg, limits::open(-90.0, 90.0),
      "About world z, 0 = straight across the aisle [deg]");
    a("heights_m", heights_m, limits::finite(), "Target heights above the ground of the initial scan [m]");
    a("extra_heights_m", extra_heights_m, limits::finite(), "Predefined scanning's additional heights [m]");
    a("lateral_m", lateral_m, limits::finite(), "Target y offsets with sign; empty: the world's rows [m]");
    a("along_m", along_m, limits::finite(), "Target x relative to the arm base [m]");
    a("replace_failed", replace_failed,
      "Predefined scanning: a scripted view that fails is replaced by the nearest reachable view of the same pattern");
    a("replace_height_step_m", replace_height_step_m, limits::in(0.001, 1.0),
      "Height step of the pattern's grid replacements are drawn from [m]");
    a("replace_azimuth_step_deg", replace_azimuth_step_deg, limits::in(0.1, 90.0),
      "Azimuth step of that grid [deg]");
    a("replace_steps", replace_steps, limits::in(1, 50), "Steps of the grid on each side of the failed view");
    a("replace_max_attempts", replace_max_attempts, limits::in(0, 100),
      "Replacements attempted per failed view at most (views without IK are skipped, not attempted)");
    a.check(!azimuths_deg.empty(), "azimuths_deg", "needs at least one azimuth");
  }
};

/// What mission.loop.exploration may name: "none" and the registry's planners that read only the
/// map (not the oracles).
std::vector<std::string> exploration_planner_names();

/// The NBV loop of one stop.
struct LoopParams {
  int views_per_stop = 12;
  int max_rounds = 1000;
  int max_idle_rounds = 10;
  int max_attempts = 60;
  double region_half_length_m = 0.45;
  double region_half_width_m = 1.2;
  double region_min_z_m = 0.05;
  double region_max_z_m = 1.8;
  bool overlap_moves = true;
  /// The planner that fills a stop when the method has nothing to attempt in a round (it ended
  /// its stop early, or offered only views already failed here), so that every method spends
  /// its views_per_stop: its views of that round are the method's ("none": the stop ends).
  std::string exploration = "frontier";

  template <class A>
  void visit(A& a) {
    a("views_per_stop", views_per_stop, limits::in(0, 10000),
      "Successful views wanted per stop beyond the initial scan's (a failed initial view is made up for)");
    a("max_rounds", max_rounds, limits::in(0, 10000), "Planning rounds per stop at most (attempts are the cap that decides)");
    a("max_idle_rounds", max_idle_rounds, limits::in(1, 10000),
      "A stop ends after this many planning rounds in a row without a view to attempt");
    a("max_attempts", max_attempts, limits::in(0, 100000), "Attempted views per stop at most (after the initial scan)");
    a("region_half_length_m", region_half_length_m, limits::positive(),
      "Targets within this of the arm base along x count [m]");
    a("region_half_width_m", region_half_width_m, limits::positive(), "... and within this laterally [m]");
    a("region_min_z_m", region_min_z_m, limits::finite(), "Lowest target height [m]");
    a("region_max_z_m", region_max_z_m, limits::finite(), "Highest target height [m]");
    a.check(region_max_z_m > region_min_z_m, "region_max_z_m", "must be above region_min_z_m");
    a("overlap_moves", overlap_moves,
      "Start a straight move while the last scan is inserted on the second core; a move whose plan changes with "
      "the scan is made again (results are the same either way; only the wall time differs)");
    a.one_of("exploration", exploration, exploration_planner_names(),
             "View planner that fills a round in which the method has nothing to attempt, so that every method "
             "spends its views_per_stop ('none': the stop ends; the method plans again first the next round)");
  }
};

/// What the mission records beside the map.
struct RecordParams {
  double truth_voxel_m = 0.01;
  double base_check_period_s = 0.02;
  bool metrics_every_view = true;
  std::vector<double> time_budgets_s = {60.0, 120.0, 180.0, 240.0};
  bool candidates = false;

  template <class A>
  void visit(A& a) {
    a("truth_voxel_m", truth_voxel_m, limits::in(0.002, 0.2),
      "Voxel of the ground-truth plant occupancy for counting contacts [m]");
    a("base_check_period_s", base_check_period_s, limits::positive(),
      "Base-vs-plants checks while driving, simulated seconds [s]");
    a("metrics_every_view", metrics_every_view, "Coverage and entropy after every view (else only per stop)");
    a("time_budgets_s", time_budgets_s, limits::positive(),
      "Simulated times T at which summary.json and the report give the coverage reached by T [s]");
    a("candidates", candidates,
      "candidates.csv: every candidate of every planning round scored by every gain and by the ground truth "
      "(the oracle; planners that sample ours' candidates)");
  }
};

/// The oracle planners (methods oracle, oracle_any; mission/oracle/oracle_planners.h). They READ THE GROUND
/// TRUTH: a view's score is the number of not yet covered target-fruit surface points it sees.
struct OracleParams {
  int render_downsample = 4;
  double depth_tolerance_m = 0.005;
  int max_views = 5;
  std::vector<double> any_radii_m = {0.25, 0.35, 0.45};
  int any_polar_count = 7;
  int any_azimuth_count = 16;
  int any_scored = 60;
  std::string candidates = "ours";

  template <class A>
  void visit(A& a) {
    a("render_downsample", render_downsample, limits::in(1, 16),
      "The truth depth render is the camera's image divided by this on each side");
    a("depth_tolerance_m", depth_tolerance_m, limits::in(0.0, 0.1),
      "A surface point is visible when its depth is within this (plus 1.5 render pixels) of the rendered depth [m]");
    a("max_views", max_views, limits::in(1, 1000), "Views returned per round, best first, tried until one succeeds");
    a("any_radii_m", any_radii_m, limits::in(0.05, 2.0), "oracle_any: sphere radii around each fruit [m]");
    a.check(any_radii_m.size() <= 16, "any_radii_m", "holds more than 16 radii (each adds a sphere of candidates per fruit)");
    a("any_polar_count", any_polar_count, limits::in(1, 100), "oracle_any: polar angles (30-150 deg) per sphere");
    a("any_azimuth_count", any_azimuth_count, limits::in(1, 360), "oracle_any: azimuths per sphere");
    a("any_scored", any_scored, limits::in(1, 100000),
      "oracle_any: views rendered per round (those with the most uncovered points in their frustum)");
    a.one_of("candidates", candidates, {"ours", "learned"},
             "oracle: the candidates it scores: ours' (clusters, spheres, ours' filter) or learned's (spheres of "
             "nbv.learned.radii_m around the shape fit's fruit centres), each through the reach test");
  }
};

/// All mission settings.
struct MissionParams {
  StopParams stops;
  ScanParams scan;
  LoopParams loop;
  RecordParams record;
  OracleParams oracle;

  template <class A>
  void visit(A& a) {
    a.section("stops", stops, "Base stops along the aisle");
    a.section("scan", scan, "The predefined views of every stop");
    a.section("loop", loop, "The NBV loop of a stop");
    a.section("record", record, "What the mission records");
    a.section("oracle", oracle, "The oracle planners (oracle, oracle_any): they read the ground truth");
  }
  bool operator==(const MissionParams& o) const { return same_params(*this, o); }
};

}  // namespace canopy::settings
