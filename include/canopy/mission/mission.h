#pragma once
// The closed-loop mission (the paper's "Overall performance" experiment) in MuJoCo: for each
// base stop along the aisle the robot drives there, takes the stop's predefined initial scan,
// then asks its view planner (ours, frontier or predefined; nbv::view_planner_registry) for
// batches of views until the stop's budget is used up, nothing is left to plan, or a cap is
// hit. Each view: IK -> OMPL plan against the current map (occupied voxels, the ground and
// the robot itself) -> execution on the simulator's servos -> when the camera reached the
// goal, the wrist camera renders from the pose actually reached, and the frame is segmented,
// inserted into the map and evaluated.
//
// The controller is a state machine around library calls: mapping, nbv and motion hold the
// algorithms (and stay MuJoCo-free); this file only sequences them, times them and records
// what happened. Contacts with the true plant geometry are counted (geometrically, against
// the world's voxelised meshes), never used for planning.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/frame.h"
#include "canopy/common/timer.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/mission/oracle.h"
#include "canopy/mission/replay.h"
#include "canopy/mission/settings.h"
#include "canopy/motion/arm_planner.h"
#include "canopy/motion/robot_model.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"

namespace canopy::mission {

/// Which part of a stop a view belongs to.
enum class ViewPhase { kInitial, kNbv, kPredefined };
const char* to_string(ViewPhase phase);

/// Where the planner looks for targets at a stop: the LoopParams box around the arm base's
/// x and the aisle's y (world-aligned).
Eigen::AlignedBox3d stop_region(const LoopParams& loop, double arm_x_m, double base_y_m);

/// Failure causes of an attempted view ("" = success), in the order they are checked.
namespace failure {
constexpr const char* kNoIk = "no_ik";                          ///< No IK solution within the joint limits.
constexpr const char* kStartInCollision = "start_in_collision"; ///< The arm (or base) already touches the map.
constexpr const char* kGoalInCollision = "goal_in_collision";   ///< Every IK solution touches the map or the robot.
constexpr const char* kPlanTimeout = "plan_timeout";            ///< No path within the planner's budget.
constexpr const char* kInvalid = "invalid_input";
constexpr const char* kNotReached = "not_reached";              ///< Executed, camera outside the tolerance.
constexpr const char* kUnstable = "unstable";                   ///< The simulation diverged (restored).
/// The cause of a failed arm plan ("" for success).
const char* of_plan(motion::PlanStatus status);
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

/// What the mission gives its planner beside the settings (nbv::ViewPlannerSettings::context):
/// the world and the simulator. The planning library's planners never read it; a planner the
/// mission's caller registers may, and one that reads the world's ground truth (an oracle)
/// must be registered with reads_ground_truth, so that its results say so.
struct MissionContext : nbv::PlannerContext {
  const world::World* world = nullptr;
  sim::Simulator* sim = nullptr;
  std::uint64_t seed = 1;
  evaluation::MetricsParams metrics;  ///< The headline rule of "covered" (the oracle's score).
  OracleParams oracle;
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

/// Hooks for the command line (progress, video, Ctrl-C) and for tests (fault injection).
struct MissionCallbacks {
  std::function<void(const std::string& message)> progress;
  /// Called every video_period_s of simulated time with a caption (stop, view, coverage).
  std::function<void(sim::Simulator& sim, const std::string& caption)> video_tick;
  double video_period_s = 0.0;
  /// Polled between steps; true ends the mission early (result marked incomplete).
  std::function<bool()> stop_requested;
  /// Called before every simulation step of a view's move (tests inject faults here).
  std::function<void(sim::Simulator& sim, int attempt)> before_step;
  /// Called after every successful view with its frame, while the simulator is in that state
  /// (before the view's map metrics are known: they are computed beside the next move).
  std::function<void(const ViewRecord& view, const LabelledFrame& frame, const sim::Simulator& sim)> on_view;
  /// Records each successful view's map changes, fruit coverage and thumbnails for the report
  /// (replay.h), beside the mission without slowing it; null records nothing.
  MapReplay* replay = nullptr;
};

/// The mission controller.
class Mission {
 public:
  /// The method is settings.method; `seed` seeds segmentation noise, the planner's draws and OMPL.
  Mission(const world::World& world, const Settings& settings, std::uint64_t seed, MissionCallbacks callbacks = {});
  ~Mission();
  Mission(const Mission&) = delete;
  Mission& operator=(const Mission&) = delete;

  /// Runs every stop; returns what happened (also when interrupted).
  MissionResult run();

  // --- Pieces, for tests -----------------------------------------------------------------
  /// Drives to stop k (0-based) and records it; false when the goal was not reached.
  bool drive_to_stop(int k);
  /// Attempts one view at the current stop.
  ViewRecord attempt(const nbv::PlannedView& view, ViewPhase phase);
  /// The predefined camera poses of stop k in the world (extra: predefined scanning's).
  std::vector<Pose> scan_views(int k, bool extra) const;
  int stop_count() const;
  const MissionResult& result() const;
  const mapping::SemanticOcTree& map() const;
  sim::Simulator& simulator();
  const motion::RobotModel& robot() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace canopy::mission
