#include "mission_impl.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/motion/reachability.h"

namespace canopy::mission {


Mission::Impl::Impl(const world::World& w, const Settings& s, std::uint64_t mission_seed, MissionCallbacks cb)
    : world(w), settings(s), seed(mission_seed), callbacks(std::move(cb)), sim(w, default_robot_config(), scene_options()),
      renderer(sim, w.spec.camera, sim::RenderOptions{false, mix_seed(mission_seed, 2), /*self_filter=*/true}),
      renderer_warm(std::async(std::launch::async, [this] { renderer.warm_up(); })),
      model(motion::RobotModel::load(sim.robot_config())), workspace(model, s.motion.workspace),
      map_env(motion::CollisionEnvironment::empty(s.mapping.map.resolution_m)),
      map_checker(model, s.motion.collision, map_env), planner(map_checker, s.motion.planner, s.motion.trajectory),
      truth_voxels(w, s.mission.record.truth_voxel_m), truth_checker(model, s.motion.collision, truth_environment()),
      map(map_params(s), w.spec.classes), inserter(map), extractor(extractor_params(s, mission_seed), w.spec.classes),
      stepper(sim, callbacks.video_period_s, video_tick(), callbacks.stop_requested),
      stops_x(stop_positions(s.mission.stops, w.spec)), evaluator(w.truth, s.mapping.metrics) {
  nbv::ViewPlannerSettings ps = canopy::settings::planner_settings(s, w.spec.camera);
  auto context = std::make_shared<MissionContext>();
  context->world = &world;
  context->sim = &sim;
  context->seed = seed;
  context->metrics = s.mapping.metrics;
  context->oracle = s.mission.oracle;
  ps.context = context;
  view_planner = nbv::make_view_planner(ps, "method");
  if (s.mission.loop.exploration != "none") {
    nbv::ViewPlannerSettings es = ps;
    es.method = nbv::MethodChoice{};
    es.method.name = s.mission.loop.exploration;
    exploration_planner = nbv::make_view_planner(es, "mission.loop.exploration");
  }
  if (s.mission.record.candidates) audit = std::make_unique<CandidateAudit>(world, sim, s);
  if (callbacks.before_step) stepper.set_before_step([this] { callbacks.before_step(sim, current_attempt); });
  update_caption();
}

std::shared_ptr<const motion::CollisionEnvironment> Mission::Impl::truth_environment() const {
  const auto [from_x, to_x] = sim.plant_window_x();
  return truth_environment(from_x, to_x);
}

std::shared_ptr<const motion::CollisionEnvironment> Mission::Impl::truth_environment(double from_x_m,
                                                                                     double to_x_m) const {
  const double res = settings.mission.record.truth_voxel_m;
  return motion::CollisionEnvironment::from_voxels(truth_voxels.voxels(from_x_m, to_x_m), res);
}

void Mission::Impl::prepare_next_window(int k) {
  // The first stop after k out of the window held: built while the robot works at the stops before it.
  int next = k + 1;
  while (next < static_cast<int>(stops_x.size()) && sim.holds_plants_near(stop_pose(next).x_m, stop_pose(next).x_m))
    ++next;
  if (next >= static_cast<int>(stops_x.size())) return;
  const double x = stop_pose(next).x_m;
  if (!sim.prepare_plants_near(x, x)) return;  // under way
  if (prepared_truth.environment.valid()) prepared_truth.environment.wait();
  prepared_truth.x_m = sim.prepared_plant_window_x();
  const auto [from_x, to_x] = prepared_truth.x_m;
  prepared_truth.environment =
      std::async(std::launch::async, [this, from_x = from_x, to_x = to_x] { return truth_environment(from_x, to_x); });
}

void Mission::Impl::update_caption() {
  caption_text = caption_line(settings.method.name, current_stop, static_cast<int>(stops_x.size()), ok_views_,
                              last_metrics.coverage);
}

BasePose Mission::Impl::stop_pose(int k) const {
  const double arm_x = model.T_base_arm().translation().x();
  return BasePose{stops_x[static_cast<std::size_t>(k)] - arm_x, settings.mission.stops.base_y_m, 0.0};
}

std::vector<Pose> Mission::Impl::scan_views(int k, bool extra) const {
  const Pose T_world_base = motion::RobotModel::T_world_base(stop_pose(k));
  std::vector<Pose> out;
  for (const Pose& T : scan_views_in_base(settings.mission.scan, world.spec, model.T_base_arm(), extra))
    out.push_back(T_world_base * T);
  return out;
}

bool Mission::Impl::drive_to_stop(int k) {
  current_stop = k;
  update_caption();
  StopRecord rec;
  rec.stop = k;
  rec.goal = stop_pose(k);
  const double t0 = sim.time();
  if (settings.mission.stops.arm_on_drive != "hold")
    rec.arm_on_drive = clear_arm_for_drive(k, rec.goal, settings.mission.stops.arm_on_drive == "always",
                                           &rec.arm_home_truth_contacts);
  progress("stop " + std::to_string(k + 1) + "/" + std::to_string(stops_x.size()) + ": driving to x = " +
           std::to_string(rec.goal.x_m));
  Stopwatch watch;
  // A long row's collision environment holds the map's voxels near the stop (issue 49): the
  // arm is planned only there (a query beyond is an error, never another answer).
  if (const double near = near_robot_m(); near > 0.0) {
    const double x = stops_x[static_cast<std::size_t>(k)];
    map_env->keep_x(x - near, x + near);
  }
  // And the map its part near the stop (its far part compact), unless the last scan is still
  // being mapped (then at the stop's first settle).
  hold_map_near(k, false);
  // A long row's rendered model holds the plants near the robot (issue 49): the stop's, built
  // again here when the stop is out of the window (the drive's video shows the stop's window).
  if (sim.show_plants_near(rec.goal.x_m, rec.goal.x_m)) {
    truth_checker.set_environment(nullptr);  // the old window's voxels go (before the new ones are made, unless prepared)
    if (prepared_truth.environment.valid() && prepared_truth.x_m == sim.plant_window_x()) {
      truth_checker.set_environment(prepared_truth.environment.get());
    } else {
      if (prepared_truth.environment.valid()) prepared_truth.environment.wait();
      prepared_truth = PreparedTruth{};
      truth_checker.set_environment(truth_environment());
    }
    const auto [first, end] = sim.plant_window();
    result.times.add(to_string(WallPhase::kScene), watch.seconds());
    progress("stop " + std::to_string(k + 1) + ": the rendered model built again for plant sections " +
             std::to_string(first + 1) + "-" + std::to_string(end) + " of " + std::to_string(sim.plant_sections()) +
             " (" + format_number(watch.seconds(), "%.1f") + " s)");
  }
  prepare_next_window(k);
  watch.restart();
  const sim::SimState before = sim.snapshot();
  const BasePose start = sim.base_pose();
  // The drive's time limit: the least time of the straight drive at the base's top speed, plus
  // mission.stops.timeout_s (a 143 m drive along a compartment needs 143 s; a fixed 30 s failed it).
  const double distance_m = std::hypot(rec.goal.x_m - start.x_m, rec.goal.y_m - start.y_m);
  const double limit_s = settings.mission.stops.timeout_s + distance_m / settings.motion.base.max_speed_m_s;
  DriveReport d;
  // The arm is checked against the true plants at the base's checks too: counted, as the base's
  // contacts are, but a touching arm does not fail the stop (mission.stops.arm_on_drive).
  int arm_contacts = 0;
  try {
    d = drive_base(
        stepper, settings.motion.base, rec.goal, limit_s,
        [this, &arm_contacts](const BasePose& b) {
          arm_contacts += truth_checker.in_collision(b, sim.arm_positions(), motion::BodySet::kArmOnly);
          return truth_checker.base_in_collision(b);
        },
        settings.mission.record.base_check_period_s);
  } catch (const SimulationDiverged& e) {
    sim.restore(before);
    ++result.unstable_faults;
    progress(std::string("drive: ") + e.what() + "; restored the last good state");
  }
  result.times.add(to_string(WallPhase::kControl), watch.seconds());
  rec.reached = sim.base_pose();
  result.base_travel_m += std::hypot(rec.reached.x_m - start.x_m, rec.reached.y_m - start.y_m);
  // A base that touched the true plants on the way failed its stop, wherever it ended.
  rec.reached_goal = d.reached && d.contacts == 0;
  if (!d.reached)
    progress("stop " + std::to_string(k + 1) + ": the base did not reach x = " + format_number(rec.goal.x_m, "%.3f") +
             " m within " + format_number(limit_s, "%.1f") + " s of simulated time (" + format_number(distance_m, "%.1f") +
             " m at most " + format_number(settings.motion.base.max_speed_m_s, "%.2f") +
             " m/s, plus mission.stops.timeout_s); it stopped " + format_number(d.position_error_m, "%.2f") + " m away");
  rec.base_truth_contacts = d.contacts;
  rec.arm_drive_truth_contacts = arm_contacts;
  rec.sim_time_s = sim.time() - t0;
  result.stops.push_back(rec);
  for_each_planner([](nbv::ViewPlanner& p) { p.begin_stop(); });
  failed_here = nbv::TakenViews(settings.nbv.views);
  return rec.reached_goal;
}

std::string Mission::Impl::clear_arm_for_drive(int k, const BasePose& goal, bool always, int* truth_contacts) {
  const ArmConfig q0 = sim.arm_positions();
  const ArmConfig& home = model.config().home;
  if (q0 == home) return always ? "home" : "free";
  const BasePose start = sim.base_pose();
  // A long row's environment holds the map near the last stop only: the sweep is tested for base
  // x within `near` less a margin of that stop, where the arm (it reaches less than a metre from
  // the base) stays inside what is held.
  constexpr double kArmReachMarginM = 1.5;
  double x_lo = -std::numeric_limits<double>::infinity(), x_hi = std::numeric_limits<double>::infinity();
  if (const double near = near_robot_m(); near > 0.0) {
    const double held_x = k > 0 ? stops_x[static_cast<std::size_t>(k - 1)] : start.x_m;
    x_lo = held_x - (near - kArmReachMarginM);
    x_hi = held_x + (near - kArmReachMarginM);
  }
  bool in_way = always;
  {
    ScopedPhase t(result.times, to_string(WallPhase::kMotionPlanning));
    scans.follow();  // the last scan's voxels in the environment
    clear_robot_volume();
    if (!always)
      in_way = motion::held_arm_sweep_hit(map_checker, start, goal, q0, 0.5 * map_env->resolution_m(), x_lo, x_hi)
                   .has_value();
  }
  if (!in_way) return "free";
  motion::PlanResult plan;
  {
    ScopedPhase t(result.times, to_string(WallPhase::kMotionPlanning));
    plan = planner.plan_to_configs(start, q0, {home}, mix_seed(seed, 2000000 + std::uint64_t(k)));
  }
  const std::string where = "stop " + std::to_string(k + 1) + "/" + std::to_string(stops_x.size()) + ": ";
  if (!plan.ok()) {
    progress(where + (always ? std::string("no plan takes the arm home before the drive (")
                             : std::string("the arm, held, would sweep mapped voxels on the drive, and no plan takes it home (")) +
             plan.message + "); driving with it held");
    return "blocked";
  }
  nbv::PlannedView to;
  to.T_world_camera = model.camera_pose(start, home);
  const ArmMove moved = move(plan, to, sim.snapshot(), result.times);
  *truth_contacts += moved.report.truth_contact_checks;
  if (!moved.diverged.empty()) ++result.unstable_faults;
  if (!moved.diverged.empty() || !moved.report.success) {
    progress(where + "the arm's move home before the drive failed (" +
             (moved.diverged.empty() ? moved.report.message : moved.diverged) + "); driving with it as it is");
    return "blocked";
  }
  return "home";
}

void Mission::Impl::note_unreached_stops() {
  if (result.stops_not_reached() == 0) return;
  std::string which;
  for (const StopRecord& s : result.stops)
    if (s.end == "base_failed") which += (which.empty() ? "" : ", ") + std::to_string(s.stop + 1);
  const std::string line = std::to_string(result.stops_not_reached()) + " of " + std::to_string(stops_x.size()) +
                           " stops not reached by the base (stop" + (result.stops_not_reached() > 1 ? "s " : " ") +
                           which + ": base_failed)";
  result.end_reason = result.complete ? line : result.end_reason + "; " + line;
}

void Mission::Impl::note_failed_attempts() {
  const int attempts = static_cast<int>(result.views.size());
  const int failed = attempts - ok_views_;
  if (attempts == 0 || 2 * failed <= attempts) return;
  std::string causes;
  for (const auto& [cause, n] : result.failures) causes += (causes.empty() ? "" : ", ") + cause + " " + std::to_string(n);
  result.end_reason += "; most attempts failed (" + std::to_string(failed) + " of " + std::to_string(attempts) +
                       (causes.empty() ? "" : ": " + causes) + ")";
}

MissionResult Mission::Impl::run() {
  if (renderer_warm.valid()) renderer_warm.get();
  elapsed_.restart();
  struct Running {
    bool& flag;
    explicit Running(bool& f) : flag(f) { flag = true; }
    ~Running() { flag = false; }
  } in_run(running);
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
  note_unreached_stops();
  note_failed_attempts();
  settle();
  // The evaluator followed every scan when metrics were kept per view: its figures are the full
  // evaluation's bit for bit (but the map's leaf counts), without a second pass over the world's
  // truth (seconds on a greenhouse compartment).
  if (settings.mission.record.metrics_every_view && evaluator.follows(map)) {
    result.final_metrics = evaluator.metrics();
    result.final_metrics.counts = map.counts();
  } else {
    map.keep_all();  // the whole map evaluated
    result.final_metrics = evaluation::evaluate_map(map, world.truth, settings.mapping.metrics);
  }
  result.zero_coverage_reason =
      zero_coverage_reason(result, world.spec.classes.target, settings.mapping.extractor.source);
  if (audit) result.candidates = audit->records();
  result.sim_time_s = sim.time();
  result.wall_time_s = elapsed_.seconds();
  return result;
}


std::unique_ptr<nbv::ViewPlanner> MissionContext::make_planner(const std::string& name,
                                                               const nbv::ViewPlannerSettings& settings) const {
  return make_oracle_planner(name, settings, *this);
}

Eigen::AlignedBox3d stop_region(const settings::LoopParams& loop, double arm_x_m, double base_y_m) {
  return Eigen::AlignedBox3d(
      Vec3(arm_x_m - loop.region_half_length_m, base_y_m - loop.region_half_width_m, loop.region_min_z_m),
      Vec3(arm_x_m + loop.region_half_length_m, base_y_m + loop.region_half_width_m, loop.region_max_z_m));
}

FailureCause failure_of_plan(motion::PlanStatus s) {
  switch (s) {
    case motion::PlanStatus::kSuccess: return FailureCause::kNone;
    case motion::PlanStatus::kNoIk: return FailureCause::kNoIk;
    case motion::PlanStatus::kStartInCollision: return FailureCause::kStartInCollision;
    case motion::PlanStatus::kGoalInCollision: return FailureCause::kGoalInCollision;
    case motion::PlanStatus::kTimeout: return FailureCause::kPlanTimeout;
    case motion::PlanStatus::kInvalidInput: return FailureCause::kInvalidInput;
  }
  return FailureCause::kInvalidInput;
}


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
const MissionResult& Mission::result() const { return impl_->result; }
const mapping::SemanticOcTree& Mission::map() const {
  // A long row's far part comes back first (SemanticOcTree::keep_x): the map is the whole one;
  // not while the mission runs (a callback's map: the scan pipeline may be reading it).
  if (!impl_->running) impl_->map.keep_all();
  return impl_->map;
}
MissionMemory Mission::memory() const {
  const Impl& m = *impl_;
  MissionMemory out;
  out.map = m.map.memory_bytes();
  out.nbv_index = m.index.memory_bytes();
  out.planning_env = m.map_env->memory_bytes();
  out.truth_env = m.truth_checker.environment() ? m.truth_checker.environment()->memory_bytes() : 0;
  out.evaluation = m.evaluator.memory_bytes();
  return out;
}
sim::Simulator& Mission::simulator() { return impl_->sim; }
const motion::RobotModel& Mission::robot() const { return impl_->model; }

}  // namespace canopy::mission
