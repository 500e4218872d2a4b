#pragma once
// What a mission records (records/, beside the controller that fills them in): one
// ViewRecord per attempted view, one StopRecord per base stop and the MissionResult of the
// whole run, with the vocabularies they use (view phases, failure causes, the wall-time
// phases). The run folder (run_folder.h), the column table of views.csv (view_columns.h) and
// the report read them; the controller (mission/mission.h) writes them.

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/enum_names.h"
#include "canopy/common/image.h"
#include "canopy/common/timer.h"
#include "canopy/common/types.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/records/schema.h"

namespace canopy::records {

/// Which part of a stop a view belongs to (kMapView: a view of `canopy map`'s list, no mission).
enum class ViewPhase { kInitial, kNbv, kPredefined, kMapView };
inline constexpr EnumName<ViewPhase> kViewPhaseNames[] = {
    {ViewPhase::kInitial, "initial"},
    {ViewPhase::kNbv, "nbv"},
    {ViewPhase::kPredefined, "predefined"},
    {ViewPhase::kMapView, "view"},
};
const char* to_string(ViewPhase phase);

/// Why an attempted view failed (kNone: it succeeded), in the order they are checked.
enum class FailureCause {
  kNone,
  kNoIk,               ///< No IK solution within the joint limits.
  kStartInCollision,   ///< The arm (or base) already touches the map.
  kGoalInCollision,    ///< Every IK solution touches the map or the robot.
  kPlanTimeout,        ///< No path within the planner's budget.
  kInvalidInput,       ///< The planner refused its input.
  kNotReached,         ///< Executed, camera outside the tolerance.
  kUnstable,           ///< The simulation diverged (restored).
};
inline constexpr EnumName<FailureCause> kFailureCauseNames[] = {
    {FailureCause::kNone, ""},
    {FailureCause::kNoIk, "no_ik"},
    {FailureCause::kStartInCollision, "start_in_collision"},
    {FailureCause::kGoalInCollision, "goal_in_collision"},
    {FailureCause::kPlanTimeout, "plan_timeout"},
    {FailureCause::kInvalidInput, "invalid_input"},
    {FailureCause::kNotReached, "not_reached"},
    {FailureCause::kUnstable, "unstable"},
};
const char* to_string(FailureCause cause);

/// Phases of the wall-time split: the mission's (the paper's Fig. 4 plus rendering and
/// evaluation) and the view planners' own parts of NBV planning (clustering, candidates,
/// filtering, scoring; the oracles' truth scoring).
enum class WallPhase {
  kMapping,
  kNbvPlanning,
  kMotionPlanning,
  kControl,
  kRendering,
  kEvaluation,
  kClustering,
  kCandidates,
  kFiltering,
  kScoring,
  kTruth,
  kScene,  ///< The rendered model built again for a long row's next window of plants (issue 49).
};
inline constexpr EnumName<WallPhase> kWallPhaseNames[] = {
    {WallPhase::kMapping, "mapping"},
    {WallPhase::kNbvPlanning, "nbv_planning"},
    {WallPhase::kMotionPlanning, "motion_planning"},
    {WallPhase::kControl, "control"},
    {WallPhase::kRendering, "rendering"},
    {WallPhase::kEvaluation, "evaluation"},
    {WallPhase::kClustering, "clustering"},
    {WallPhase::kCandidates, "candidates"},
    {WallPhase::kFiltering, "filtering"},
    {WallPhase::kScoring, "scoring"},
    {WallPhase::kTruth, "truth"},
    {WallPhase::kScene, "scene"},
};
const char* to_string(WallPhase phase);

/// The categories of the run-time plot (the paper's Fig. 4 and its two additions), each the sum
/// of some wall-time phases: runtime.csv's columns, the report's run-time bars.
enum class PlotCategory { kMapping, kNbvPlanning, kMotionPlanning, kControl, kRendering, kEvaluation };
inline constexpr EnumName<PlotCategory> kPlotCategoryNames[] = {
    {PlotCategory::kMapping, "mapping"},
    {PlotCategory::kNbvPlanning, "nbv_planning"},
    {PlotCategory::kMotionPlanning, "motion_planning"},
    {PlotCategory::kControl, "control"},
    {PlotCategory::kRendering, "rendering"},
    {PlotCategory::kEvaluation, "evaluation"},
};
const char* to_string(PlotCategory category);

/// A plot category: its title and the wall-time phases it sums.
struct PlotCategoryInfo {
  PlotCategory category;
  const char* title;               ///< "NBV planning".
  std::vector<WallPhase> phases;
  bool paper = false;              ///< One of the paper's Fig. 4 four (its "total run time").
};
/// Every plot category, in the plot's order.
const std::vector<PlotCategoryInfo>& plot_categories();

/// The colour a view's camera is drawn in, by phase or failed: the report's frustums, the bags'
/// markers and the plots share it.
Rgb8 view_colour(ViewPhase phase, bool success);
/// The legend's words for a phase ("initial scan", "next-best view", ...).
const char* view_phase_legend(ViewPhase phase);

/// The vocabularies above as JSON, exported once into the report's data (and to Python):
/// view_phases [{name, colour "#rrggbb", legend}], failed_view_colour, failure_causes [names],
/// wall_phases [names], plot_categories [{name, title, phases, paper}].
nlohmann::json vocabulary_json();

/// One candidate of one planning round, scored by every gain and by the truth.
struct CandidateRecord {
  int stop = 0;
  int round = 0;               ///< Planning round of the stop (0-based).
  int views_before = 0;        ///< Successful views of the mission before the round.
  int cluster = -1;
  Pose T_world_camera = Pose::Identity();
  bool chosen = false;         ///< The planner's best view of the round.
  double planner_gain = 0.0;   ///< The planner's own score.
  std::size_t frustum = 0;     ///< Uncovered truth points in its frustum.
  std::size_t truth = 0;       ///< Uncovered truth points it sees (the oracle's score).
  std::vector<double> scores;  ///< audit_score_names() order.
  std::vector<float> features; ///< nbv::view_feature_names() order (a learned scorer's input).
};

/// One attempted view. Its fields are named, with unit and meaning, once: in visit() (the
/// schema, schema.h), which views.csv, the report's data, canopy map's history and Python's
/// dicts are written by.
struct ViewRecord {
  int attempt = 0;
  int stop = 0;
  ViewPhase phase = ViewPhase::kInitial;
  std::string source;
  bool success = false;
  FailureCause failure = FailureCause::kNone;
  std::string message;
  Pose T_goal = Pose::Identity();
  Pose T_reached = Pose::Identity();  ///< Camera pose the frame was rendered from (success).
  double position_error_m = 0.0, angle_error_rad = 0.0;
  double gain = 0.0;
  int cluster = -1;
  Vec3 target = Vec3::Zero();
  int successful_views = 0;
  double coverage = 0.0;         ///< Under the metrics rule.
  double entropy = 0.0;
  double coverage_paper = 0.0, entropy_paper = 0.0;
  double coverage_prototype = 0.0, entropy_prototype = 0.0;
  double sim_time_s = 0.0;
  double move_time_s = 0.0;
  int truth_contacts = 0;
  int self_contacts = 0;
  long target_points = 0;
  long true_target_pixels = 0;
  double arm_path_rad = 0.0;
  double base_travel_m = 0.0;
  std::string start_repair;
  /// The field's figures of the map after this view (evaluation::MapMetrics, headline rule).
  double fruits_sc50 = 0.0, fruits_sc80 = 0.0;
  int fruit_clusters = 0, fruits_matched = 0;
  double detection_precision = 0.0, detection_recall = 0.0, detection_f1 = 0.0;
  double centre_error_m = 0.0, voxel_volume_error = 0.0, ellipsoid_volume_error = 0.0;  ///< NaN without a match.
  double fruit_voxel_precision = 0.0, false_fruit_volume_m3 = 0.0;
  PhaseTimes times;              ///< Wall time by phase (timing.csv, not a field).
  /// OMPL iterations of the plan that decided the attempt (motion::PlanResult::iterations;
  /// timing.csv, not a field).
  int plan_iterations = 0;

  /// The schema of a view: every field in views.csv's column order, then those kept out of
  /// it. `method` is the run's (the same on every row).
  template <class A>
  void visit(A& a, const std::string& method);

 private:
  /// A reached pose's part exists only for a view that reached its goal.
  std::optional<double> reached_part(double value) const { return success ? std::optional<double>(value) : std::nullopt; }
  /// An error that needs a matched fruit is nothing (NaN) before one is matched.
  static std::optional<double> when_finite(double value) {
    return std::isfinite(value) ? std::optional<double>(value) : std::nullopt;
  }
  Quat reached_q() const { return Quat(T_reached.linear()); }
};

template <class A>
void ViewRecord::visit(A& a, const std::string& method) {
  using F = Field;
  using RG = ReportGroup;
  const Vec3 goal = T_goal.translation(), got = T_reached.translation();
  a("attempt", attempt, F("", "attempt number over the mission, from 0"));
  a("stop", stop, F("", "base stop, from 0"));
  a("method", method, F("", "the run's view planner (`method.name`)"));
  a.choice("phase", phase, kViewPhaseNames, F("", "`initial`, `nbv` or `predefined`"));
  a("source", source, F("", "what chose the view: `initial`, `nbv`, `roi`, `exploration`, `predefined`, `replacement`, ..."));
  a("success", success, F("", "1 when the camera reached the goal and the frame was mapped, else 0"));
  a.choice("failure", failure, kFailureCauseNames,
           F("", "why the view failed (`no_ik`, `goal_in_collision`, `plan_timeout`, `not_reached`, ...); empty on success"));
  a("goal_x", goal.x(), F("m", "goal camera position x (world frame)"));
  a("goal_y", goal.y(), F("m", "goal camera position y"));
  a("goal_z", goal.z(), F("m", "goal camera position z"));
  a("reached_x", reached_part(got.x()), F("m", "camera position the frame was rendered from, x (empty: failed view)"));
  a("reached_y", reached_part(got.y()), F("m", "reached camera position y (empty: failed view)"));
  a("reached_z", reached_part(got.z()), F("m", "reached camera position z (empty: failed view)"));
  a("reached_qw", reached_part(reached_q().w()), F("", "reached camera orientation, unit quaternion w (empty: failed view)"));
  a("reached_qx", reached_part(reached_q().x()), F("", "reached camera orientation x (empty: failed view)"));
  a("reached_qy", reached_part(reached_q().y()), F("", "reached camera orientation y (empty: failed view)"));
  a("reached_qz", reached_part(reached_q().z()), F("", "reached camera orientation z (empty: failed view)"));
  a("position_error_m", position_error_m, F("m", "distance of the reached camera from the goal"));
  a("angle_error_deg", angle_error_rad * 180.0 / M_PI, F("deg", "angle between the reached and the goal camera orientation"));
  a("gain", gain, F("", "the planner's information gain of the view (0 for scripted views)"));
  a("cluster", cluster, F("", "the fruit cluster the view was planned for (-1: none)"));
  a("successful_views", successful_views, F("", "successful views so far, this one included"));
  a("coverage", coverage,
    F("", "fruit surface coverage after the view (headline rule, `mapping.metrics.rule`)").map_figure("coverage"));
  a("entropy", entropy, F("nats", "fruit entropy after the view (headline rule)").map_figure("total_entropy"));
  a("sim_time_s", sim_time_s,
    F("s", "simulated time at the end of the attempt")
        .curve_at(4)
        .report("simulated_time_s", "motion_cost/simulated_time_s", RG::kMotionCost, 13));
  a("move_time_s", move_time_s, F("s", "simulated time of the view's move"));
  a("truth_contacts", truth_contacts,
    F("", "executed arm states in contact with the true plants (counted, never planned with)"));
  a("self_contacts", self_contacts, F("", "simulation steps with a robot-robot contact"));
  a("coverage_paper", coverage_paper, F("", "fruit surface coverage under the paper's rule").map_figure("coverage_paper"));
  a("entropy_paper", entropy_paper, F("nats", "fruit entropy under the paper's rule").map_figure("entropy_paper"));
  a("coverage_prototype", coverage_prototype,
    F("", "fruit surface coverage under the prototype's rule").map_figure("coverage_prototype"));
  a("entropy_prototype", entropy_prototype,
    F("nats", "fruit entropy under the prototype's rule").map_figure("entropy_prototype"));
  a("arm_path_rad", arm_path_rad,
    F("rad", "joint-space length of the trajectory executed (report: the mission's total)")
        .report("arm_path_rad", "motion_cost/arm_path_rad", RG::kMotionCost, 11));
  a("base_travel_m", base_travel_m,
    F("m", "base travel of the mission so far").report("base_travel_m", "motion_cost/base_travel_m", RG::kMotionCost, 12, "%.2f"));
  a("fruits_sc50", fruits_sc50,
    F("", "share of the target fruits with a coverage of 50 % or more")
        .map_figure("fruits_sc50")
        .report("fruits_sc50", "final/fruits_sc50", RG::kCompleteness, 7));
  a("fruits_sc80", fruits_sc80,
    F("", "share of the target fruits with a coverage of 80 % or more")
        .map_figure("fruits_sc80")
        .curve_at(1)
        .report("fruits_sc80", "final/fruits_sc80", RG::kCompleteness, 8));
  a("fruit_clusters", fruit_clusters, F("", "clusters of fruit voxels in the map").map_figure());
  a("fruits_matched", fruits_matched, F("", "clusters matched one-to-one to a true target fruit").map_figure());
  a("detection_precision", detection_precision,
    F("", "matched clusters / clusters").map_figure().report("detection_precision", "final/detection/precision", RG::kDetection, 1));
  a("detection_recall", detection_recall,
    F("", "matched fruits / target fruits").map_figure().report("detection_recall", "final/detection/recall", RG::kDetection, 2));
  a("detection_f1", detection_f1,
    F("", "F1 of detection precision and recall")
        .map_figure("detection_f1")
        .curve_at(2)
        .report("detection_f1", "final/detection/f1", RG::kDetection, 3));
  a("centre_error_m", when_finite(centre_error_m),
    F("m", "mean distance of a matched cluster's centroid from its fruit's centre (empty: no match)")
        .map_figure()
        .report("detection_centre_error_m", "final/detection/centre_error_m", RG::kDetection, 4));
  a("voxel_volume_error", when_finite(voxel_volume_error),
    F("", "mean relative error of a matched cluster's voxel volume (empty: no match)")
        .map_figure()
        .report("detection_voxel_volume_error", "final/detection/voxel_volume_error", RG::kDetection, 5));
  a("ellipsoid_volume_error", when_finite(ellipsoid_volume_error),
    F("", "mean relative error of a matched cluster's moment ellipsoid volume (empty: no match)")
        .map_figure()
        .report("detection_ellipsoid_volume_error", "final/detection/ellipsoid_volume_error", RG::kDetection, 6));
  a("fruit_voxel_precision", fruit_voxel_precision,
    F("", "share of the fruit voxels that lie on a true target fruit")
        .map_figure("fruit_voxel_precision")
        .curve_at(3)
        .report("fruit_voxel_precision", "final/fruit_voxel_precision/precision", RG::kCompleteness, 9));
  a("false_fruit_volume_m3", false_fruit_volume_m3,
    F("m³", "volume of the fruit voxels off every true fruit (report: in cm³)")
        .map_figure()
        .report("false_fruit_volume_cm3", "final/fruit_voxel_precision/false_volume_m3", RG::kCompleteness, 10, "%.2f", 1e6));
  // Kept out of views.csv.
  a("goal_pose", T_goal, F("", "the goal camera pose T_world_camera (optical frame)").not_csv());
  a("reached_pose", success ? std::optional<Pose>(T_reached) : std::nullopt,
    F("", "the camera pose the frame was rendered from (none: failed view)").not_csv());
  a("target", target, F("m", "the point the planner aimed the view at").not_csv());
  a("message", message, F("", "the failure's details, or what was done").not_csv());
  a("start_repair", start_repair,
    F("", "the arm's start was in collision: what, and how it was left (empty: it was free)").not_csv());
  a("target_points", target_points, F("", "points of the view's cloud labelled the target class").not_csv());
  a("true_target_pixels", true_target_pixels, F("", "target-class pixels in the frame's true labels").not_csv());
}

/// One base stop (summary.json's "stops", the report's stops). Its fields are named once, in
/// visit().
struct StopRecord {
  int stop = 0;
  BasePose goal, reached;
  bool reached_goal = false;
  int base_truth_contacts = 0;
  int arm_drive_truth_contacts = 0;
  int arm_home_truth_contacts = 0;
  int initial_attempted = 0, initial_ok = 0;
  long initial_target_points = 0;
  long initial_true_target_pixels = 0;
  int nbv_attempted = 0, nbv_ok = 0;
  int scripted_replaced = 0;
  int replacement_attempts = 0;
  int refused = 0;
  int guarded = 0;
  int exploration_rounds = 0;
  int rounds = 0;
  std::map<std::string, int> failures;  ///< Failed attempts by cause (FailureCause names, in name order).
  std::string end_reason;
  /// budget_met, planner_done (it has nothing left to see), attempt_cap, round_cap,
  /// idle_rounds (no view to attempt in max_idle_rounds rounds), interrupted, base_failed.
  std::string end;
  int budget = 0;
  int start_repairs = 0;
  /// The arm before the drive here (mission.stops.arm_on_drive): held (as the last view left it),
  /// free (clear: its sweep along the drive passes no mapped voxel, so it was held), home (moved to
  /// the robot's home configuration first, or there already) or blocked (no move home; held).
  std::string arm_on_drive = "held";
  double sim_time_s = 0.0;
  /// Counts an attempt made at this stop (attempted, successful, target points, failures).
  void count(const ViewRecord& view);

  /// The schema of a stop.
  template <class A>
  void visit(A& a) {
    using F = Field;
    a("stop", stop, F("", "base stop, from 0"));
    a("goal", goal, F("m, m, rad", "the base's goal: x, y, yaw"));
    a("reached", reached, F("m, m, rad", "the base pose reached: x, y, yaw"));
    a("reached_goal", reached_goal, F("", "reached within tolerance without touching the plants"));
    a("base_truth_contacts", base_truth_contacts, F("", "base-vs-plant contacts seen while driving here (geometric)"));
    a("arm_drive_truth_contacts", arm_drive_truth_contacts,
      F("", "arm-vs-plant contacts seen while driving here, at the base's checks (geometric; counted, never planned "
            "with)"));
    a("arm_home_truth_contacts", arm_home_truth_contacts,
      F("", "executed arm states in contact with the true plants on the move home before the drive here "
            "(mission.stops.arm_on_drive)"));
    a("initial_attempted", initial_attempted, F("", "views of the initial scan attempted"));
    a("initial_successful", initial_ok, F("", "views of the initial scan that succeeded"));
    a("initial_target_points", initial_target_points, F("", "points the initial scan's views labelled the target class"));
    a("initial_true_target_pixels", initial_true_target_pixels,
      F("", "target-class pixels in the initial scan's true labels"));
    a("initial_scan_saw_no_target", initial_ok > 0 && initial_target_points == 0,
      F("", "the initial scan's views succeeded but labelled no target point (also a WARNING progress line)"));
    a("nbv_attempted", nbv_attempted, F("", "views after the initial scan attempted"));
    a("nbv_successful", nbv_ok, F("", "views after the initial scan that succeeded"));
    a("scripted_replaced", scripted_replaced,
      F("", "failed scripted views replaced by a successful pattern neighbour (predefined)"));
    a("replacement_attempts", replacement_attempts,
      F("", "replacement views attempted (counted in the attempted views too)"));
    a("refused", refused,
      F("", "scripted views the planner refused before any move (no collision-free IK goal; not attempts)"));
    a("guarded", guarded,
      F("", "views a planner offered again after they failed here for a cause of their own, dropped by the mission "
            "(not attempts)"));
    a("exploration_rounds", exploration_rounds,
      F("", "rounds planned by mission.loop.exploration because the method had nothing to attempt"));
    a("rounds", rounds, F("", "planning rounds"));
    a("failures", failures, F("", "failed attempts by cause"));
    a("arm_on_drive", arm_on_drive,
      F("", "the arm before the drive here: `held`, `free` (not in the way), `home` (moved home first) or `blocked` "
            "(no move home); mission.stops.arm_on_drive"));
    a("end_reason", end_reason, F("", "why the stop's loop ended, in a line"));
    a("end", end, F("", "why, as a code: `budget_met`, `planner_done`, `attempt_cap`, `round_cap`, `idle_rounds`, "
                        "`interrupted` or `base_failed`"));
    a("budget", budget, F("", "successful views wanted at this stop (the initial scan's + views_per_stop)"));
    a("successful", initial_ok + nbv_ok, F("", "successful views at this stop"));
    a("start_repairs", start_repairs, F("", "attempts whose arm start was in collision and was repaired"));
    a("sim_time_s", sim_time_s, F("s", "simulated time spent at (and driving to) this stop"));
  }
};

/// The whole run.
struct MissionResult {
  std::vector<ViewRecord> views;
  std::vector<StopRecord> stops;
  bool complete = true;          ///< False when interrupted (the views so far are valid).
  /// Why the run ended: "all stops done", "interrupted", or "K of N stops not reached (...)"
  /// when the base failed to reach a stop (stops_not_reached); followed by "; most attempts
  /// failed (...)" when fewer than half of the attempts succeeded.
  std::string end_reason = "all stops done";
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  double arm_path_rad = 0.0;     ///< Joint-space path of every executed trajectory.
  double base_travel_m = 0.0;    ///< Base travel between stops.
  PhaseTimes times;              ///< mapping, nbv_planning, motion_planning, control, rendering, evaluation.
  evaluation::MapMetrics final_metrics;
  int unstable_faults = 0;
  /// Moves started before the last scan was in the map (mission.loop.overlap_moves), and those
  /// of them kept (the plan with the scan was the same); the others were made again.
  int overlapped_moves = 0;
  int overlapped_kept = 0;
  std::map<std::string, int> failures;  ///< Failed attempts by cause (FailureCause names, in name order).
  /// When the final fruit coverage is 0: why (no successful view, no target pixel segmented,
  /// ...); empty otherwise.
  std::string zero_coverage_reason;
  /// Every candidate of every planning round scored by every gain and the truth
  /// (mission.record.candidates; empty otherwise).
  std::vector<CandidateRecord> candidates;
  int successful_views() const;
  /// The stops whose base never arrived (end "base_failed"): a run with any did not serve
  /// its rows, and the command fails (exit code 1), whatever its coverage.
  int stops_not_reached() const;
};

/// Why a run whose views succeeded ended at coverage 0, from the points its segmentation
/// labelled `target` and the target pixels of the renderer's true labels in its frames: no
/// fruit in view, a segmentation that labelled none of the fruit it saw (colour: the fruit's
/// colours outside the bands), or target points none of which was kept on a fruit.
std::string zero_coverage_cause(const std::string& target, perception::LabelSource labels, long target_points,
                                long true_target_pixels);

/// Why a finished mission's final coverage is 0 ("" when it is not): no target fruit in the
/// world, no successful view, or zero_coverage_cause of its views.
std::string zero_coverage_reason(const MissionResult& result, const std::string& target, perception::LabelSource labels);
/// Copies the map's figures (coverage, entropy, the field's metrics) into a view's record.
void set_map_metrics(const evaluation::MapMetrics& metrics, ViewRecord* record);
/// The progress line of a recorded attempt ("stop 2/5: nbv view 31 ok (views 30, SC ...)").
std::string progress_line(const ViewRecord& view, int stops, double elapsed_s);
/// The video's caption ("ours | stop 2/5 | views 30 | fruit SC 0.15"); `stop` counts from 0.
std::string caption_line(const std::string& method, int stop, int stops, int views, double coverage);

}  // namespace canopy::records
