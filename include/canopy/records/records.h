#pragma once
// What a mission records (records/, beside the controller that fills them in): one
// ViewRecord per attempted view, one StopRecord per base stop and the MissionResult of the
// whole run, with the vocabularies they use (view phases, failure causes, the wall-time
// phases). The run folder (run_folder.h), the column table of views.csv (view_columns.h) and
// the report read them; the controller (mission/mission.h) writes them.

#include <map>
#include <string>
#include <vector>

#include "canopy/common/timer.h"
#include "canopy/common/types.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::records {

/// Which part of a stop a view belongs to.
enum class ViewPhase { kInitial, kNbv, kPredefined };
const char* to_string(ViewPhase phase);

/// Failure causes of an attempted view ("" = success), in the order they are checked.
namespace failure {
constexpr const char* kNoIk = "no_ik";                          ///< No IK solution within the joint limits.
constexpr const char* kStartInCollision = "start_in_collision"; ///< The arm (or base) already touches the map.
constexpr const char* kGoalInCollision = "goal_in_collision";   ///< Every IK solution touches the map or the robot.
constexpr const char* kPlanTimeout = "plan_timeout";            ///< No path within the planner's budget.
constexpr const char* kInvalid = "invalid_input";
constexpr const char* kNotReached = "not_reached";              ///< Executed, camera outside the tolerance.
constexpr const char* kUnstable = "unstable";                   ///< The simulation diverged (restored).
}  // namespace failure

/// Phases of the wall-time split (the paper's Fig. 4 plus rendering and evaluation); the
/// view planners add clustering, candidates, filtering and scoring.
namespace phase {
constexpr const char* kMapping = "mapping";
constexpr const char* kNbvPlanning = "nbv_planning";
constexpr const char* kMotionPlanning = "motion_planning";
constexpr const char* kControl = "control";
constexpr const char* kRendering = "rendering";
constexpr const char* kEvaluation = "evaluation";
}  // namespace phase

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

/// One attempted view.
struct ViewRecord {
  int attempt = 0;               ///< Attempt number over the mission (0-based).
  int stop = 0;
  ViewPhase phase = ViewPhase::kInitial;
  std::string source;            ///< "initial", "nbv", "roi", "exploration", "predefined", "replacement".
  bool success = false;
  std::string failure;           ///< A failure:: cause, empty on success.
  std::string message;           ///< Details of the failure.
  Pose T_goal = Pose::Identity();
  Pose T_reached = Pose::Identity();  ///< Camera pose the frame was rendered from (success).
  double position_error_m = 0.0, angle_error_rad = 0.0;
  double gain = 0.0;
  int cluster = -1;
  Vec3 target = Vec3::Zero();    ///< The point the planner aimed the view at (kept out of views.csv).
  int successful_views = 0;      ///< Successful views so far (this one included).
  double coverage = 0.0;         ///< Fruit surface coverage after this view (metrics rule).
  double entropy = 0.0;          ///< Fruit entropy after this view [nats] (metrics rule).
  double coverage_paper = 0.0, entropy_paper = 0.0;          ///< The same under each rule.
  double coverage_prototype = 0.0, entropy_prototype = 0.0;
  double sim_time_s = 0.0;       ///< Simulated time at the end of the attempt.
  double move_time_s = 0.0;      ///< Simulated time of the move.
  int truth_contacts = 0;        ///< Executed states in contact with the true plants.
  int self_contacts = 0;         ///< Steps with a robot-robot contact in MuJoCo.
  long target_points = 0;        ///< Points of its cloud labelled the target class (kept out of views.csv).
  long true_target_pixels = 0;   ///< Target-class pixels in its frame's true labels (kept out of views.csv).
  double arm_path_rad = 0.0;     ///< Joint-space length of the trajectory executed (sum of |dq| over its waypoints).
  double base_travel_m = 0.0;    ///< Base travel of the mission so far (straight lines between stops).
  std::string start_repair;      ///< The arm's start was in collision: what, and how it was left ("" = it was free).
  /// The field's figures of the map after this view (evaluation::MapMetrics, headline rule).
  double fruits_sc50 = 0.0, fruits_sc80 = 0.0;
  int fruit_clusters = 0, fruits_matched = 0;
  double detection_precision = 0.0, detection_recall = 0.0, detection_f1 = 0.0;
  double centre_error_m = 0.0, voxel_volume_error = 0.0, ellipsoid_volume_error = 0.0;  ///< NaN without a match.
  double fruit_voxel_precision = 0.0, false_fruit_volume_m3 = 0.0;
  PhaseTimes times;              ///< Wall time by phase (kept out of views.csv).
};

/// One base stop.
struct StopRecord {
  int stop = 0;
  BasePose goal, reached;
  bool reached_goal = false;     ///< Reached within tolerance without touching the plants.
  int base_truth_contacts = 0;   ///< Base-vs-plant contacts seen while driving here (geometric).
  int initial_attempted = 0, initial_ok = 0;
  /// Points the initial scan's views labelled the target class; 0 after successful views
  /// means the segmentation saw no target at the stop (noted in the log and summary.json).
  long initial_target_points = 0;
  long initial_true_target_pixels = 0;  ///< Target-class pixels in those views' true labels.
  int nbv_attempted = 0, nbv_ok = 0;
  int scripted_replaced = 0;     ///< Failed scripted views replaced by a successful pattern neighbour (predefined).
  int replacement_attempts = 0;  ///< Replacement views attempted (counted in initial_ / nbv_attempted too).
  /// Scripted views the planner refused before any move (no collision-free IK goal at this
  /// base, nbv.predefined.goal_test_at_planning) and handed on to be replaced; not attempts.
  int refused = 0;
  /// Views a planner offered again after they had failed at this stop for a cause of their own
  /// (nbv::joins_failed_views): dropped by the mission before any move; not attempts.
  int guarded = 0;
  /// Rounds planned by mission.loop.exploration because the method had nothing to attempt.
  int exploration_rounds = 0;
  int rounds = 0;
  std::map<std::string, int> failures;
  std::string end_reason;        ///< Why the stop's loop ended (one line).
  /// Why, as a code: budget_met, planner_done (it has nothing left to see), attempt_cap,
  /// round_cap, idle_rounds (no view to attempt in max_idle_rounds rounds), interrupted,
  /// base_failed.
  std::string end;
  int budget = 0;                ///< Successful views wanted at this stop (initial scan's + views_per_stop).
  int start_repairs = 0;         ///< Attempts whose arm start was in collision and was repaired.
  double sim_time_s = 0.0;       ///< Simulated time spent at (and driving to) this stop.
  /// Counts an attempt made at this stop (attempted, successful, target points, failures).
  void count(const ViewRecord& view);
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
  std::map<std::string, int> failures;
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
