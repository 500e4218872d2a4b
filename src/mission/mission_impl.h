#pragma once
// The mission's state and steps (internal to the mission): mission.cpp sets it up and runs the
// stops, mission_attempt.cpp makes one attempt (plan, move, look, record), mission_stop.cpp
// runs a stop's scripted views and its NBV loop.

#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/random.h"
#include "canopy/evaluation/incremental_evaluator.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/mission/mission.h"
#include "canopy/mission/oracle/candidate_audit.h"
#include "canopy/mission/oracle/oracle_planners.h"
#include "canopy/mission/scan_views.h"
#include "canopy/mission/stepping.h"
#include "canopy/motion/arm_planner.h"
#include "canopy/motion/collision.h"
#include "canopy/motion/execution.h"
#include "canopy/motion/workspace_filter.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/sim/renderer.h"
#include "scan_pipeline.h"

namespace canopy::mission {

// The records the controller fills in and the settings it reads, by their short names.
using records::MissionResult;
using records::StopRecord;
using records::ViewPhase;
using records::ViewRecord;
using records::caption_line;
using records::progress_line;
using records::set_map_metrics;
using records::zero_coverage_reason;
using records::FailureCause;
using records::WallPhase;
using settings::Settings;

struct Mission::Impl {
  const world::World& world;
  Settings settings;
  std::uint64_t seed;
  MissionCallbacks callbacks;

  sim::Simulator sim;
  sim::Renderer renderer;
  // The renderer compiles its shaders on a second thread while the rest is set up.
  std::future<void> renderer_warm;
  motion::RobotModel model;
  motion::WorkspaceFilter workspace;
  // Planning knows only the map; the truth (voxelised plant meshes) only counts contacts.
  std::shared_ptr<motion::CollisionEnvironment> map_env;
  motion::CollisionChecker map_checker;
  motion::ArmPlanner planner;
  // The true plants' voxels per window, each plant's kept while windows overlap (issue 49).
  mutable evaluation::WindowVoxels truth_voxels;
  motion::CollisionChecker truth_checker;
  mapping::SemanticOcTree map;
  mapping::ScanInserter inserter;
  perception::SemanticExtractor extractor;
  nbv::VoxelIndex index;
  std::unique_ptr<nbv::ViewPlanner> view_planner;
  // mission.loop.exploration: plans the rounds in which view_planner has nothing to attempt
  // (null: "none"). Told every view and outcome, as view_planner is.
  std::unique_ptr<nbv::ViewPlanner> exploration_planner;
  // The guard: views that failed at this stop for a cause of their own (nbv::joins_failed_views),
  // never attempted again at it, whichever planner offers them.
  nbv::TakenViews failed_here;
  std::unique_ptr<CandidateAudit> audit;  // mission.record.candidates: reads the ground truth
  SimStepper stepper;
  std::vector<double> stops_x;

  MissionResult result;
  int current_stop = 0;
  // True while run() runs: Mission::map() then leaves a long row's far part out (a callback's
  // read of it is an internal error), as the scan pipeline may be reading the map.
  bool running = false;
  int current_attempt = 0;
  std::string caption_text;
  evaluation::IncrementalEvaluator evaluator;  // the metrics after each view (reads the ground truth)
  evaluation::MapMetrics last_metrics;

  // The rendered model per plant section (issue 49): a 12 m window of 3 m sections, so that a
  // compartment's row is never one compiled model; a world that fits in one window or has
  // fewer than 3 M triangles (every world file but the compartment's) is built whole, as it
  // always was.
  static sim::SceneOptions scene_options() {
    sim::SceneOptions o;
    o.plant_window_m = 12.0;
    return o;
  }
  static mapping::SemanticMapParams map_params(const Settings& s) { return s.mapping.map; }
  static perception::ExtractorParams extractor_params(const Settings& s, std::uint64_t seed) {
    perception::ExtractorParams p = s.mapping.extractor;
    p.seed = mix_seed(seed, 1);
    return p;
  }
  Impl(const world::World& w, const Settings& s, std::uint64_t mission_seed, MissionCallbacks cb);
  std::function<void()> video_tick() {
    if (!callbacks.video_tick) return nullptr;
    return [this] { callbacks.video_tick(sim, caption_text); };
  }
  void progress(const std::string& m) const {
    if (callbacks.progress) callbacks.progress(m);
  }
  void update_caption();
  // Issue 49: the half-length of the stretch around a stop that the index and the collision
  // environment hold (MissionCallbacks::near_robot_m); 0: the whole map.
  double near_robot_m() const {
    if (callbacks.near_robot_m >= 0.0) return callbacks.near_robot_m;
    return sim.plants_windowed() ? Mission::kNearRobotM : 0.0;
  }
  // Issue 49: the map holds its subtrees within twice that of the stop, the rest moved out as
  // compact bytes (SemanticOcTree::keep_x); the index's reads beyond its own stretch land in
  // the map's, and a read beyond the map's is an internal error, never another answer.
  // A per-view callback (a video's map inset, an MCAP's map cloud, Python's on_view) may walk
  // the whole map (Mission::map()) after every view: with one, the map is kept whole.
  double map_near_m() const { return callbacks.on_view ? 0.0 : 2.0 * near_robot_m(); }
  // The true plants as voxels, for the robot's contacts: the plants the rendered model holds
  // (a long row's window, issue 49: the base's contacts on a drive are counted with the plants
  // of the window it drives to; every plant of a world that fits in one window).
  std::shared_ptr<const motion::CollisionEnvironment> truth_environment() const;
  // The truth's voxels of the plants in base x [from, to) (unbounded: every plant). Any thread.
  std::shared_ptr<const motion::CollisionEnvironment> truth_environment(double from_x_m, double to_x_m) const;
  // A long row's next window (issue 49): its rendered model and truth voxels built on another
  // thread while the robot works at stop k, for the first later stop out of the window held.
  void prepare_next_window(int k);
  struct PreparedTruth {
    std::pair<double, double> x_m;
    std::future<std::shared_ptr<const motion::CollisionEnvironment>> environment;
  };
  PreparedTruth prepared_truth;
  BasePose stop_pose(int k) const;
  std::vector<Pose> scan_views(int k, bool extra) const;
  StopRecord& stop_record() { return result.stops.back(); }
  bool drive_to_stop(int k);
  // mission.stops.arm_on_drive = clear: before the drive to `goal`, the arm goes home when, held
  // as it is, it would pass through the map's occupied voxels on the straight drive; `always`
  // (arm_on_drive = always): whenever it is not home. The move's contacts with the true plants
  // are added to `truth_contacts`. Returns the StopRecord::arm_on_drive code.
  std::string clear_arm_for_drive(int k, const BasePose& goal, bool always, int* truth_contacts);

  // A new attempt's record.
  ViewRecord open_record(const nbv::PlannedView& view, ViewPhase phase) const;

  // Ends an attempt: its outcome ("" = success), the figures after it, the counters.
  ViewRecord& close_record(ViewRecord& rec, FailureCause cause, const std::string& message);

  // Waits for the last scan's mapping (scan_pipeline.h) and completes the records that waited
  // for its metrics.
  void settle();
  // The map held near stop k (SemanticOcTree::keep_x; map_near_m() > 0), once per stop: now when
  // the scan pipeline is idle or `wait`, else at the next settle (the last scan's mapping reads
  // and changes the map; waiting for it before a drive would change which moves overlap).
  void hold_map_near(int k, bool wait);
  int map_held_stop = -1;

  // A move may start before the last scan is in the map (mission.loop.overlap_moves): with no
  // video or test hook to see it, when the scan's environment is not followed yet, and only as
  // a straight move (its plan draws no random number). Once the scan is in, the move is planned
  // again; a different plan undoes the move and makes the new one, so results never change.
  bool may_overlap() const {
    return settings.mission.loop.overlap_moves && scans.unfollowed() && !callbacks.video_tick && !callbacks.before_step;
  }

  // The arm plan to one of `goals`, in the map's environment without the robot's own volume.
  motion::PlanResult plan_move(const BasePose& base, const ArmConfig& q0, const std::vector<ArmConfig>& goals);
  // plan_move's plan when it is the straight line, without searching (an overlapped move keeps no other).
  std::optional<motion::PlanResult> straight_move(const BasePose& base, const ArmConfig& q0,
                                                  const std::vector<ArmConfig>& goals);

  // The planned move on the simulator's servos from `before`, the current state.
  ArmMove move(const motion::PlanResult& plan, const nbv::PlannedView& view, const sim::SimState& before,
               PhaseTimes& times);

  // A plan that repaired its start in collision and then failed: the repair move is made on
  // its own, so that the next attempt starts free (motion::ArmPlanner::repair_start).
  void leave_collision(const motion::PlanResult& plan, const nbv::PlannedView& view, PhaseTimes& times);

  // Ends the mission when a stop was requested (Ctrl-C, SIGTERM, a Python KeyboardInterrupt):
  // polled between attempts and planning rounds, as the stepper polls between steps.
  void check_stop() const {
    if (callbacks.stop_requested && callbacks.stop_requested()) throw StopRequested();
  }

  // The wrist camera's frame from the pose reached, and its segmented cloud.
  struct Look {
    LabelledFrame frame;
    perception::LabelledCloud cloud;
    Image<std::uint8_t> mapped_labels;  // the cloud's pixel labels (after noise), for the report
  };
  Look take_look(PhaseTimes& times);
  ViewRecord attempt(const nbv::PlannedView& view, ViewPhase phase);

  // The robot's own volume out of the planner's collision environment, at the arm's state now:
  // before every use of it at planning (the view filter, the goal test, a replacement's test)
  // as before every arm plan, so that voxels mapped where the arm stands are no obstacle.
  void clear_robot_volume();

  // The planners that are told each view and outcome: the method's and the exploration one.
  template <class F>
  void for_each_planner(F&& f) {
    f(*view_planner);
    if (exploration_planner) f(*exploration_planner);
  }

  // Records an attempt in the mission and stop, and tells the planner its outcome.
  void record(const ViewRecord& v, const nbv::PlannedView& view);

  // The progress line of a recorded attempt.
  void report(const ViewRecord& v) const;

  // Orders views by an open tour from the current arm state; views without IK are returned
  // in `unreachable`.
  std::vector<nbv::PlannedView> tour(std::vector<nbv::PlannedView> views, std::vector<nbv::PlannedView>* unreachable);

  // Executes views in order; stops once `wanted` succeeded (<0: all), returns the successes
  // (and the views that failed in `failed`, when given).
  int execute(const std::vector<nbv::PlannedView>& views, ViewPhase phase, int wanted, int* attempts_left,
              std::vector<nbv::PlannedView>* failed = nullptr);

  // Planners that replace failed scripted views (PlannerTraits::replaces_failed) get them,
  // when mission.scan.replace_failed allows it.
  bool replaces_failed_scripted() const {
    return view_planner->traits().replaces_failed && settings.mission.scan.replace_failed;
  }

  // Hands each failed scripted view to the planner with what it may replace it by: the scan
  // pattern's views around it, nearest first (mission.scan.replace_*), the stop's whole pattern,
  // the IK test at this base and an attempt that records (and spends `attempts_left`, when
  // given). Which views are attempted is the planner's choice. Returns the views replaced.
  int replace_failed(const std::vector<nbv::PlannedView>& failed, ViewPhase phase, int* attempts_left);

  // Records chosen views without IK as failed attempts (spending `attempts_left`, when given,
  // and stopping when it is spent).
  void record_unreachable(const std::vector<nbv::PlannedView>& views, ViewPhase phase, int* attempts_left = nullptr);

  // The predefined views of a stop: unreachable ones are skipped and counted, the rest taken in tour order.
  void scripted(const std::vector<Pose>& poses, ViewPhase phase);

  // Ends the stop's loop: why, as a code and a line.
  static void end_stop(StopRecord& s, const char* code, const std::string& why) {
    s.end = code;
    s.end_reason = why;
  }

  // The NBV loop of the current stop: until the stop's budget of successful views is met (the
  // initial scan's views and views_per_stop more), the planner has nothing left to see, or the
  // stop's attempts (mission.loop.max_attempts) are spent. Planning rounds that attempt nothing
  // are bounded by max_idle_rounds in a row.
  void nbv_loop(int k, int scan_views_count);

  // The mission's end reason: a run most of whose attempts failed says so.
  void note_unreached_stops();
  void note_failed_attempts();
  MissionResult run();


  Stopwatch elapsed_;
  int ok_views_ = 0;  // successful views so far (MissionResult::successful_views() without the count)
  std::size_t background_view_ = 0;  // the record of the scan in the pipeline
  // The last scan's mapping; last, so it ends before the members it uses are destroyed.
  ScanPipeline scans{map, inserter, index, evaluator, *map_env, callbacks.replay};
};

}  // namespace canopy::mission
