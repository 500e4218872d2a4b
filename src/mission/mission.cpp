#include "canopy/mission/mission.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <optional>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/mission/stepping.h"
#include "canopy/motion/arm_planner.h"
#include "canopy/evaluation/incremental_evaluator.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/motion/collision.h"
#include "canopy/motion/execution.h"
#include "canopy/motion/reachability.h"
#include "canopy/motion/tour.h"
#include "canopy/motion/view_reach.h"
#include "canopy/motion/workspace_filter.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/sim/renderer.h"
#include "scan_pipeline.h"

namespace canopy::mission {

namespace {

using namespace phase;

}  // namespace

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
  motion::CollisionChecker truth_checker;
  mapping::SemanticOcTree map;
  mapping::ScanInserter inserter;
  perception::SemanticExtractor extractor;
  nbv::VoxelIndex index;
  std::unique_ptr<nbv::ViewPlanner> view_planner;
  std::unique_ptr<CandidateAudit> audit;  // mission.record.candidates: reads the ground truth
  SimStepper stepper;
  std::vector<double> stops_x;

  MissionResult result;
  int current_stop = 0;
  int current_attempt = 0;
  std::string caption_text;
  evaluation::IncrementalEvaluator evaluator;  // the metrics after each view (reads the ground truth)
  evaluation::MapMetrics last_metrics;

  static mapping::SemanticMapParams map_params(const Settings& s) { return s.mapping.map; }
  static perception::ExtractorParams extractor_params(const Settings& s, std::uint64_t seed) {
    perception::ExtractorParams p = s.mapping.extractor;
    p.seed = mix_seed(seed, 1);
    return p;
  }

  Impl(const world::World& w, const Settings& s, std::uint64_t mission_seed, MissionCallbacks cb)
      : world(w), settings(s), seed(mission_seed), callbacks(std::move(cb)), sim(w, default_robot_config()),
        renderer(sim, w.spec.camera, sim::RenderOptions{false, mix_seed(mission_seed, 2), /*self_filter=*/true}),
        renderer_warm(std::async(std::launch::async, [this] { renderer.warm_up(); })),
        model(motion::RobotModel::load(sim.robot_config())), workspace(model, s.motion.workspace),
        map_env(motion::CollisionEnvironment::empty(s.mapping.map.resolution_m)),
        map_checker(model, s.motion.collision, map_env), planner(map_checker, s.motion.planner, s.motion.trajectory),
        truth_checker(model, s.motion.collision,
                      motion::CollisionEnvironment::from_voxels(
                          evaluation::world_occupied_voxels(w, s.mission.record.truth_voxel_m), s.mission.record.truth_voxel_m)),
        map(map_params(s), w.spec.classes), inserter(map), extractor(extractor_params(s, mission_seed), w.spec.classes),
        stepper(sim, callbacks.video_period_s, video_tick(), callbacks.stop_requested),
        stops_x(stop_positions(s.mission.stops, w.spec)), evaluator(w.truth, s.mapping.metrics) {
    nbv::ViewPlannerSettings ps;
    ps.params = s.nbv;
    ps.intrinsics = w.spec.camera;
    ps.method = s.method;
    auto context = std::make_shared<MissionContext>();
    context->world = &world;
    context->sim = &sim;
    context->seed = seed;
    context->metrics = s.mapping.metrics;
    context->oracle = s.mission.oracle;
    ps.context = context;
    view_planner = nbv::make_view_planner(ps, "method");
    if (s.mission.record.candidates) audit = std::make_unique<CandidateAudit>(world, sim, s);
    if (callbacks.before_step) stepper.set_before_step([this] { callbacks.before_step(sim, current_attempt); });
    update_caption();
  }

  std::function<void()> video_tick() {
    if (!callbacks.video_tick) return nullptr;
    return [this] { callbacks.video_tick(sim, caption_text); };
  }

  void progress(const std::string& m) const {
    if (callbacks.progress) callbacks.progress(m);
  }

  void update_caption() {
    caption_text = caption_line(settings.method.name, current_stop, static_cast<int>(stops_x.size()), ok_views_,
                                last_metrics.coverage);
  }

  BasePose stop_pose(int k) const {
    const double arm_x = model.T_base_arm().translation().x();
    return BasePose{stops_x[static_cast<std::size_t>(k)] - arm_x, settings.mission.stops.base_y_m, 0.0};
  }

  std::vector<Pose> scan_views(int k, bool extra) const {
    const Pose T_world_base = motion::RobotModel::T_world_base(stop_pose(k));
    std::vector<Pose> out;
    for (const Pose& T : scan_views_in_base(settings.mission.scan, world.spec, model.T_base_arm(), extra))
      out.push_back(T_world_base * T);
    return out;
  }

  StopRecord& stop_record() { return result.stops.back(); }

  bool drive_to_stop(int k) {
    current_stop = k;
    update_caption();
    StopRecord rec;
    rec.stop = k;
    rec.goal = stop_pose(k);
    const double t0 = sim.time();
    progress("stop " + std::to_string(k + 1) + "/" + std::to_string(stops_x.size()) + ": driving to x = " +
             std::to_string(rec.goal.x_m));
    const Stopwatch watch;
    const sim::SimState before = sim.snapshot();
    const BasePose start = sim.base_pose();
    DriveReport d;
    try {
      d = drive_base(stepper, settings.motion.base, rec.goal, settings.mission.stops.timeout_s,
                     [this](const BasePose& b) { return truth_checker.base_in_collision(b); },
                     settings.mission.record.base_check_period_s);
    } catch (const SimulationDiverged& e) {
      sim.restore(before);
      ++result.unstable_faults;
      progress(std::string("drive: ") + e.what() + "; restored the last good state");
    }
    result.times.add(kControl, watch.seconds());
    rec.reached = sim.base_pose();
    result.base_travel_m += std::hypot(rec.reached.x_m - start.x_m, rec.reached.y_m - start.y_m);
    // A base that touched the true plants on the way failed its stop, wherever it ended.
    rec.reached_goal = d.reached && d.contacts == 0;
    rec.base_truth_contacts = d.contacts;
    rec.sim_time_s = sim.time() - t0;
    result.stops.push_back(rec);
    view_planner->begin_stop();
    return rec.reached_goal;
  }

  // A new attempt's record.
  ViewRecord open_record(const nbv::PlannedView& view, ViewPhase phase) const {
    ViewRecord rec;
    rec.attempt = current_attempt;
    rec.stop = current_stop;
    rec.phase = phase;
    rec.source = phase == ViewPhase::kInitial && view.source != "replacement" ? "initial" : view.source;
    rec.T_goal = view.T_world_camera;
    rec.gain = view.gain;
    rec.cluster = view.cluster;
    rec.target = view.target;
    return rec;
  }

  // Ends an attempt: its outcome ("" = success), the figures after it, the counters.
  ViewRecord& close_record(ViewRecord& rec, const std::string& cause, const std::string& message) {
    rec.failure = cause;
    rec.message = message;
    rec.success = cause.empty();
    rec.successful_views = ok_views_ + rec.success;
    rec.sim_time_s = sim.time();
    rec.base_travel_m = result.base_travel_m;
    set_map_metrics(last_metrics, &rec);
    if (!rec.success) ++result.failures[cause];
    result.times.merge(rec.times);
    ++current_attempt;
    return rec;
  }

  // Waits for the last scan's mapping (scan_pipeline.h) and completes the records that waited
  // for its metrics.
  void settle() {
    if (!scans.busy()) return;
    const PhaseTimes t = scans.settle();
    if (settings.mission.record.metrics_every_view) last_metrics = evaluator.metrics();
    result.times.merge(t);
    for (std::size_t i = background_view_; i < result.views.size(); ++i) {
      ViewRecord& v = result.views[i];
      if (i == background_view_) v.times.merge(t);
      set_map_metrics(last_metrics, &v);
      report(v);
    }
    update_caption();
  }

  // A move may start before the last scan is in the map (mission.loop.overlap_moves): with no
  // video or test hook to see it, when the scan's environment is not followed yet, and only as
  // a straight move (its plan draws no random number). Once the scan is in, the move is planned
  // again; a different plan undoes the move and makes the new one, so results never change.
  bool may_overlap() const {
    return settings.mission.loop.overlap_moves && scans.unfollowed() && !callbacks.video_tick && !callbacks.before_step;
  }

  // The arm plan to one of `goals`, in the map's environment without the robot's own volume.
  motion::PlanResult plan_move(const BasePose& base, const ArmConfig& q0, const std::vector<ArmConfig>& goals) {
    // Where the robot is cannot be an obstacle (leaves it brushed aside, seen up close).
    map_env->clear_robot_volume(model, base, q0, settings.motion.collision.environment_padding_m);
    return planner.plan_to_configs(base, q0, goals, mix_seed(seed, 1000000 + std::uint64_t(current_attempt)));
  }

  // The planned move on the simulator's servos from `before`, the current state.
  ArmMove move(const motion::PlanResult& plan, const nbv::PlannedView& view, const sim::SimState& before,
               PhaseTimes& times) {
    ScopedPhase phase_time(times, kControl);
    return move_arm(stepper, model, plan.trajectory, view.T_world_camera, settings.motion.execution, &truth_checker,
                    before);
  }

  // A plan that repaired its start in collision and then failed: the repair move is made on
  // its own, so that the next attempt starts free (motion::ArmPlanner::repair_start).
  void leave_collision(const motion::PlanResult& plan, const nbv::PlannedView& view, PhaseTimes& times) {
    if (!plan.repaired || plan.repair.size() < 2) return;
    motion::PlanResult leave;
    leave.trajectory = planner.repair_trajectory(plan);
    nbv::PlannedView to = view;
    to.T_world_camera = model.camera_pose(sim.base_pose(), plan.repair.back());
    const ArmMove moved = move(leave, to, sim.snapshot(), times);
    if (!moved.diverged.empty()) ++result.unstable_faults;
  }

  // Ends the mission when a stop was requested (Ctrl-C, SIGTERM, a Python KeyboardInterrupt):
  // polled between attempts and planning rounds, as the stepper polls between steps.
  void check_stop() const {
    if (callbacks.stop_requested && callbacks.stop_requested()) throw StopRequested();
  }

  // The wrist camera's frame from the pose reached, and its segmented cloud.
  struct Look {
    LabelledFrame frame;
    perception::LabelledCloud cloud;
  };
  Look take_look(PhaseTimes& times) {
    Look look;
    {
      ScopedPhase phase_time(times, kRendering);
      look.frame = renderer.render_wrist_camera();
    }
    ScopedPhase phase_time(times, kMapping);
    look.cloud = extractor.extract(look.frame);
    return look;
  }

  ViewRecord attempt(const nbv::PlannedView& view, ViewPhase phase) {
    ViewRecord rec = open_record(view, phase);
    const BasePose base = sim.base_pose();
    const ArmConfig q0 = sim.arm_positions();
    auto finish = [&](const std::string& cause, const std::string& message) { return close_record(rec, cause, message); };

    // Motion planning: IK, then OMPL against the map.
    motion::PlanResult plan;
    std::vector<ArmConfig> goals;
    bool overlap = false;
    {
      ScopedPhase phase_time(rec.times, kMotionPlanning);
      goals = motion::view_goal_configs(model, view, base, q0);
      if (goals.empty()) return finish(failure::kNoIk, "no IK solution within the joint limits");
      overlap = may_overlap();
      if (!overlap) scans.follow();
      plan = plan_move(base, q0, goals);
      if (overlap && !(plan.ok() && plan.direct)) {  // planned again with the scan
        overlap = false;
        scans.follow();
        plan = plan_move(base, q0, goals);
      }
    }
    rec.start_repair = plan.repaired ? plan.repair_note : "";
    if (!plan.ok()) {
      leave_collision(plan, view, rec.times);
      return finish(failure::of_plan(plan.status), plan.message);
    }

    // Control; an overlapped move is kept when the plan with the last scan is the same. Its
    // frame is drawn and segmented before that check, while the last scan is still going in;
    // a move made again discards them and puts the noise generators' states back.
    const sim::SimState before = sim.snapshot();
    ArmMove moved = move(plan, view, before, rec.times);
    std::optional<Look> look;
    if (overlap) {
      const Rng depth_noise = renderer.noise_state(), label_noise = extractor.noise_state();
      if (moved.diverged.empty() && moved.report.success) look = take_look(rec.times);
      motion::PlanResult checked;
      {
        ScopedPhase phase_time(rec.times, kMotionPlanning);
        scans.follow();
        checked = plan_move(base, q0, goals);
      }
      ++result.overlapped_moves;
      if (checked.status == plan.status && checked.path == plan.path) {
        ++result.overlapped_kept;
      } else {
        sim.restore(before);
        renderer.set_noise_state(depth_noise);
        extractor.set_noise_state(label_noise);
        look.reset();
        plan = std::move(checked);
        rec.start_repair = plan.repaired ? plan.repair_note : "";
        if (!plan.ok()) {
          leave_collision(plan, view, rec.times);
          return finish(failure::of_plan(plan.status), plan.message);
        }
        moved = move(plan, view, before, rec.times);
      }
    }
    const std::vector<ArmConfig>& w = plan.trajectory.waypoints();
    for (std::size_t i = 1; i < w.size(); ++i) rec.arm_path_rad += motion::joint_distance(w[i - 1], w[i]);
    result.arm_path_rad += rec.arm_path_rad;
    rec.move_time_s = moved.time_s;
    if (!moved.diverged.empty()) {
      ++result.unstable_faults;
      progress(std::string("view ") + std::to_string(current_attempt) + ": " + moved.diverged +
               "; restored the state before the move");
      return finish(failure::kUnstable, moved.diverged);
    }
    const motion::MoveReport& report = moved.report;
    rec.move_time_s = report.duration_s;
    rec.truth_contacts = report.truth_contact_checks;
    rec.self_contacts = report.self_contact_steps;
    rec.position_error_m = report.position_error_m;
    rec.angle_error_rad = report.angle_error_rad;
    if (!report.success) return finish(failure::kNotReached, report.message);

    if (!look) look = take_look(rec.times);
    const LabelledFrame& frame = look->frame;
    rec.T_reached = frame.T_world_camera;
    rec.target_points = static_cast<long>(look->cloud.stats.target_points);
    rec.true_target_pixels = static_cast<long>(look->cloud.stats.true_target_pixels);
    // The insertion, the NBV index and the metrics on the second core beside the next move
    // (scan_pipeline.h), the planner's environment before it plans.
    {
      ScopedPhase phase_time(rec.times, kMapping);
      settle();  // the last scan's mapping ends before the map changes
      if (callbacks.replay) callbacks.replay->record_frame(frame);
      scans.start(std::move(look->cloud), settings.mission.record.metrics_every_view);
      background_view_ = result.views.size();  // the row this record will take
    }
    view_planner->taken(frame.T_world_camera);
    close_record(rec, "", "camera within tolerance");
    if (callbacks.on_view) {
      scans.follow();  // the callback may read the map
      callbacks.on_view(rec, frame, sim);
    }
    update_caption();
    return rec;
  }

  // Records an attempt in the mission and stop, and tells the planner its outcome.
  void record(const ViewRecord& v, const nbv::PlannedView& view) {
    result.views.push_back(v);
    ok_views_ += v.success;
    StopRecord& s = stop_record();
    s.count(v);
    s.start_repairs += !v.start_repair.empty();
    if (!scans.busy()) report(v);  // else once its metrics are known (settle)
    nbv::ViewOutcome o;
    o.view = view;
    o.success = v.success;
    o.failure = v.failure;
    o.detail = v.start_repair.empty() ? v.message : v.message + " (start repaired: " + v.start_repair + ")";
    o.T_reached = v.T_reached;
    o.stop = v.stop;
    o.attempt = v.attempt;
    o.phase = to_string(v.phase);
    o.start_repaired = !v.start_repair.empty();
    view_planner->outcome(o);
  }

  // The progress line of a recorded attempt.
  void report(const ViewRecord& v) const {
    progress(progress_line(v, static_cast<int>(stops_x.size()), elapsed_.seconds()));
  }

  // Orders views by an open tour from the current arm state; views without IK are returned
  // in `unreachable`.
  std::vector<nbv::PlannedView> tour(std::vector<nbv::PlannedView> views, std::vector<nbv::PlannedView>* unreachable) {
    return motion::tour_order(model, settings.motion.tour, sim.base_pose(), sim.arm_positions(), std::move(views),
                              unreachable);
  }

  // Executes views in order; stops once `wanted` succeeded (<0: all), returns the successes
  // (and the views that failed in `failed`, when given).
  int execute(const std::vector<nbv::PlannedView>& views, ViewPhase phase, int wanted, int* attempts_left,
              std::vector<nbv::PlannedView>* failed = nullptr) {
    int ok = 0;
    for (const nbv::PlannedView& v : views) {
      if (wanted >= 0 && ok >= wanted) break;
      if (attempts_left && *attempts_left <= 0) break;
      check_stop();
      if (attempts_left) --*attempts_left;
      const ViewRecord r = attempt(v, phase);
      record(r, v);
      ok += r.success;
      if (!r.success && failed) failed->push_back(v);
    }
    return ok;
  }

  // Planners that replace failed scripted views (PlannerTraits::replaces_failed) get them,
  // when mission.scan.replace_failed allows it.
  bool replaces_failed_scripted() const {
    return view_planner->traits().replaces_failed && settings.mission.scan.replace_failed;
  }

  // Hands each failed scripted view to the planner with what it may replace it by: the scan
  // pattern's views around it, nearest first (mission.scan.replace_*), the stop's whole pattern,
  // the IK test at this base and an attempt that records (and spends `attempts_left`, when
  // given). Which views are attempted is the planner's choice. Returns the views replaced.
  int replace_failed(const std::vector<nbv::PlannedView>& failed, ViewPhase phase, int* attempts_left) {
    const ScanParams& scan = settings.mission.scan;
    const Pose T_world_base = motion::RobotModel::T_world_base(stop_pose(current_stop));
    std::vector<ScanView> pattern = scan_view_list(scan, world.spec, model.T_base_arm(), false);
    for (const ScanView& v : scan_view_list(scan, world.spec, model.T_base_arm(), true)) pattern.push_back(v);
    nbv::FailedScriptedView req;
    for (const ScanView& v : pattern) req.scripted.push_back(T_world_base * v.T_base_camera);
    req.max_attempts = scan.replace_max_attempts;
    req.attempts_left = attempts_left;
    req.reachable = [&](const nbv::PlannedView& v) {
      ScopedPhase t(result.times, kNbvPlanning);
      return motion::has_free_goal(model, &planner.goal_checker(), v, sim.base_pose(), sim.arm_positions());
    };
    req.attempt = [&](const nbv::PlannedView& v) {
      check_stop();
      if (attempts_left) --*attempts_left;
      ++stop_record().replacement_attempts;
      const ViewRecord r = attempt(v, phase);
      record(r, v);
      return r.success;
    };
    int ok = 0;
    for (const nbv::PlannedView& f : failed) {
      const ScanView* spec = nullptr;
      for (const ScanView& v : pattern)
        if (same_view(T_world_base * v.T_base_camera, f.T_world_camera)) spec = &v;
      if (!spec) continue;
      req.failed = f;
      req.options.clear();
      {
        ScopedPhase t(result.times, kNbvPlanning);
        for (const ScanView& c : scan_replacements(scan, model.T_base_arm(), *spec)) {
          nbv::PlannedView v;
          v.T_world_camera = T_world_base * c.T_base_camera;
          v.target = v.T_world_camera * Vec3(0, 0, scan.distance_m);
          v.source = "replacement";
          req.options.push_back(v);
        }
      }
      const bool replaced = view_planner->replace_failed(req);
      stop_record().scripted_replaced += replaced;
      ok += replaced;
    }
    return ok;
  }

  // Records chosen views without IK as failed attempts (spending `attempts_left`, when given,
  // and stopping when it is spent).
  void record_unreachable(const std::vector<nbv::PlannedView>& views, ViewPhase phase, int* attempts_left = nullptr) {
    for (const nbv::PlannedView& v : views) {
      if (attempts_left && *attempts_left <= 0) break;
      check_stop();
      if (attempts_left) --*attempts_left;
      ViewRecord r = open_record(v, phase);
      record(close_record(r, failure::kNoIk, "no IK solution within the joint limits"), v);
    }
  }

  // The predefined views of a stop: unreachable ones are skipped and counted, the rest taken in tour order.
  void scripted(const std::vector<Pose>& poses, ViewPhase phase) {
    std::vector<nbv::PlannedView> views;
    for (const Pose& T : poses) {
      nbv::PlannedView v;
      v.T_world_camera = T;
      v.target = T * Vec3(0, 0, settings.mission.scan.distance_m);
      v.source = phase == ViewPhase::kInitial ? "initial" : "predefined";
      views.push_back(v);
    }
    std::vector<nbv::PlannedView> unreachable;
    std::vector<nbv::PlannedView> ordered;
    {
      ScopedPhase t(result.times, kNbvPlanning);
      ordered = tour(views, &unreachable);
    }
    record_unreachable(unreachable, phase);
    std::vector<nbv::PlannedView> failed = unreachable;
    execute(ordered, phase, -1, nullptr, &failed);
    if (replaces_failed_scripted()) replace_failed(failed, phase, nullptr);
  }

  // Ends the stop's loop: why, as a code and a line.
  static void end_stop(StopRecord& s, const char* code, const std::string& why) {
    s.end = code;
    s.end_reason = why;
  }

  // The NBV loop of the current stop: until the stop's budget of successful views is met (the
  // initial scan's views and views_per_stop more), the planner has nothing left to see, or the
  // stop's attempts (mission.loop.max_attempts) are spent. Planning rounds that attempt nothing
  // are bounded by max_idle_rounds in a row.
  void nbv_loop(int k, int scan_views_count) {
    const LoopParams& loop = settings.mission.loop;
    StopRecord& s = stop_record();
    s.budget = scan_views_count + loop.views_per_stop;
    int ok = 0, attempts_left = loop.max_attempts, idle = 0;
    const int wanted_total = std::max(0, s.budget - s.initial_ok);
    motion::NextViewsRequest req;
    req.region = stop_region(loop, stops_x[static_cast<std::size_t>(k)], settings.mission.stops.base_y_m);
    const nbv::PlannerTraits traits = view_planner->traits();
    if (traits.scripted) req.scripted = scan_views(k, true);
    const motion::StopArm arm{model, workspace, &planner.goal_checker(), settings.motion.tour};
    // The goal test of frontier and predefined sees the environment the arm planner will see:
    // without the robot's own volume (plan_move clears it the same way before the move).
    req.before_goal_test = [this, &req] {
      map_env->clear_robot_volume(model, req.base, req.q, settings.motion.collision.environment_padding_m);
    };
    for (;;) {
      check_stop();
      if (ok >= wanted_total) {
        end_stop(s, "budget_met", "view budget of the stop reached");
        break;
      }
      if (attempts_left <= 0) {
        end_stop(s, "attempt_cap", "attempt cap reached (mission.loop.max_attempts = " + std::to_string(loop.max_attempts) + ")");
        break;
      }
      if (s.rounds >= loop.max_rounds) {
        end_stop(s, "round_cap", "round cap reached (mission.loop.max_rounds = " + std::to_string(loop.max_rounds) + ")");
        break;
      }
      motion::NextViews next;
      scans.follow_index();  // the last scan in the map and the index; its metrics may come later
      {
        const Stopwatch watch;
        req.base = sim.base_pose();
        req.q = sim.arm_positions();
        req.T_world_camera = sim.camera_pose();
        req.budget = wanted_total - ok;
        req.seed = mix_seed(seed, 5000 + std::uint64_t(k) * 1000 + std::uint64_t(s.rounds));
        req.max_views = static_cast<std::size_t>(attempts_left);
        if (audit) req.on_scored = audit->observer();
        next = motion::next_views(map, index, *view_planner, arm, req);
        result.times.merge(next.batch.times);
        // The planner's own phases are in batch.times; the rest (tour, bookkeeping) here.
        result.times.add(kNbvPlanning, std::max(0.0, watch.seconds() - next.batch.times.total()));
      }
      check_stop();  // a stop requested while the planner ran (a Python planner's KeyboardInterrupt) wins
      const nbv::ViewBatch& batch = next.batch;
      if (audit) {
        ScopedPhase t(result.times, kEvaluation);
        audit->end_round(map, index, batch, k, s.rounds, ok_views_, req.seed);
      }
      const std::vector<nbv::PlannedView>& ordered = next.ordered;
      const std::vector<nbv::PlannedView>& unreachable = next.unreachable;
      ++s.rounds;
      s.refused += static_cast<int>(batch.refused.size());
      if (batch.views.empty() && batch.refused.empty()) {
        const std::string why = batch.reason.empty() ? "nothing left to plan" : batch.reason;
        if (batch.finished) {
          end_stop(s, "planner_done", "the planner has nothing left to see: " + why);
          break;
        }
        if (++idle >= loop.max_idle_rounds) {  // e.g. every frontier view rejected, round after round
          end_stop(s, "idle_rounds", "no view to attempt in " + std::to_string(idle) + " rounds in a row: " + why);
          break;
        }
        continue;  // sample anew next round
      }
      idle = 0;
      const ViewPhase phase = traits.scripted ? ViewPhase::kPredefined : ViewPhase::kNbv;
      record_unreachable(unreachable, phase, &attempts_left);
      const int wanted = wanted_total - ok;
      if (batch.order == nbv::BatchOrder::kTour) {
        std::vector<nbv::PlannedView> failed = unreachable;
        failed.insert(failed.end(), batch.refused.begin(), batch.refused.end());  // not attempts
        ok += execute(ordered, phase, traits.execute_whole_batch ? -1 : wanted, &attempts_left, &failed);
        if (replaces_failed_scripted()) ok += replace_failed(failed, phase, &attempts_left);
      } else {
        ok += execute(ordered, phase, 1, &attempts_left);  // frontier: the first view that succeeds
      }
      if (batch.last_of_stop) {
        if (ok >= wanted_total) end_stop(s, "budget_met", "view budget of the stop reached");
        else end_stop(s, "planner_done", "the planner has nothing left to see: " + batch.reason);
        break;
      }
    }
  }

  // The mission's end reason: a run most of whose attempts failed says so.
  void note_failed_attempts() {
    const int attempts = static_cast<int>(result.views.size());
    const int failed = attempts - ok_views_;
    if (attempts == 0 || 2 * failed <= attempts) return;
    std::string causes;
    for (const auto& [cause, n] : result.failures) causes += (causes.empty() ? "" : ", ") + cause + " " + std::to_string(n);
    result.end_reason += "; most attempts failed (" + std::to_string(failed) + " of " + std::to_string(attempts) +
                         (causes.empty() ? "" : ": " + causes) + ")";
  }

  MissionResult run() {
    if (renderer_warm.valid()) renderer_warm.get();
    elapsed_.restart();
    try {
      for (int k = 0; k < static_cast<int>(stops_x.size()); ++k) {
        const double t0 = sim.time();
        if (!drive_to_stop(k)) {
          StopRecord& s = stop_record();
          end_stop(s, "base_failed",
                   s.base_truth_contacts > 0 ? "the base touched the plants while driving (failed stop)"
                                             : "the base did not reach the stop");
          progress("stop " + std::to_string(k + 1) + ": " + s.end_reason + "; skipping the stop");
          continue;
        }
        const std::vector<Pose> scan = scan_views(k, false);
        scripted(scan, ViewPhase::kInitial);
        const StopRecord& s = stop_record();
        if (s.initial_ok > 0 && s.initial_target_points == 0)
          progress("stop " + std::to_string(k + 1) + "/" + std::to_string(stops_x.size()) + ": WARNING: the initial scan's " +
                   std::to_string(s.initial_ok) + " views segmented no '" + world.spec.classes.target + "' pixel (labels: " +
                   perception::to_string(settings.mapping.extractor.source) + "); the renderer's true labels show " +
                   (s.initial_true_target_pixels > 0
                        ? std::to_string(s.initial_true_target_pixels) + " such pixels in them"
                        : std::string("none either: no fruit in view")));
        nbv_loop(k, static_cast<int>(scan.size()));
        stop_record().sim_time_s = sim.time() - t0;
      }
    } catch (const StopRequested&) {
      result.complete = false;
      result.end_reason = "interrupted";
      if (!result.stops.empty() && result.stops.back().end.empty()) end_stop(result.stops.back(), "interrupted", "interrupted");
    }
    note_failed_attempts();
    settle();
    result.final_metrics = evaluation::evaluate_map(map, world.truth, settings.mapping.metrics);
    result.zero_coverage_reason =
        zero_coverage_reason(result, world.spec.classes.target, settings.mapping.extractor.source);
    if (audit) result.candidates = audit->records();
    result.sim_time_s = sim.time();
    result.wall_time_s = elapsed_.seconds();
    return result;
  }

  Stopwatch elapsed_;
  int ok_views_ = 0;  // successful views so far (MissionResult::successful_views() without the count)
  std::size_t background_view_ = 0;  // the record of the scan in the pipeline
  // The last scan's mapping; last, so it ends before the members it uses are destroyed.
  ScanPipeline scans{map, inserter, index, evaluator, *map_env, callbacks.replay};
};

Mission::Mission(const world::World& world, const Settings& settings, std::uint64_t seed, MissionCallbacks callbacks)
    : impl_(std::make_unique<Impl>(world, settings, seed, std::move(callbacks))) {}
Mission::~Mission() = default;
MissionResult Mission::run() { return impl_->run(); }
bool Mission::drive_to_stop(int k) { return impl_->drive_to_stop(k); }
ViewRecord Mission::attempt(const nbv::PlannedView& view, ViewPhase phase) {
  impl_->record(impl_->attempt(view, phase), view);
  impl_->settle();
  return impl_->result.views.back();
}
std::vector<Pose> Mission::scan_views(int k, bool extra) const { return impl_->scan_views(k, extra); }
int Mission::stop_count() const { return static_cast<int>(impl_->stops_x.size()); }
const MissionResult& Mission::result() const { return impl_->result; }
const mapping::SemanticOcTree& Mission::map() const { return impl_->map; }
sim::Simulator& Mission::simulator() { return impl_->sim; }
const motion::RobotModel& Mission::robot() const { return impl_->model; }

}  // namespace canopy::mission
