#include "mission_impl.h"

#include <optional>

#include "canopy/motion/view_reach.h"

namespace canopy::mission {


ViewRecord Mission::Impl::open_record(const nbv::PlannedView& view, ViewPhase phase) const {
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

ViewRecord& Mission::Impl::close_record(ViewRecord& rec, FailureCause cause, const std::string& message) {
  rec.failure = cause;
  rec.message = message;
  rec.success = cause == FailureCause::kNone;
  rec.successful_views = ok_views_ + rec.success;
  rec.sim_time_s = sim.time();
  rec.base_travel_m = result.base_travel_m;
  set_map_metrics(last_metrics, &rec);
  if (!rec.success) ++result.failures[to_string(cause)];
  result.times.merge(rec.times);
  ++current_attempt;
  return rec;
}

void Mission::Impl::hold_map_near(int k, bool wait) {
  const double near = map_near_m();
  if (near <= 0.0 || map_held_stop == k) return;
  if (scans.busy()) {
    if (!wait) return;
    settle();
  }
  const double x = stops_x[static_cast<std::size_t>(k)];
  map.keep_x(x - near, x + near);
  map_held_stop = k;
}

void Mission::Impl::settle() {
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

motion::PlanResult Mission::Impl::plan_move(const BasePose& base, const ArmConfig& q0,
                                            const std::vector<ArmConfig>& goals) {
  // Where the robot is cannot be an obstacle (leaves it brushed aside, seen up close).
  map_env->clear_robot_volume(model, base, q0, settings.motion.collision.environment_padding_m);
  return planner.plan_to_configs(base, q0, goals, mix_seed(seed, 1000000 + std::uint64_t(current_attempt)));
}

std::optional<motion::PlanResult> Mission::Impl::straight_move(const BasePose& base, const ArmConfig& q0,
                                                               const std::vector<ArmConfig>& goals) {
  map_env->clear_robot_volume(model, base, q0, settings.motion.collision.environment_padding_m);
  return planner.straight_plan(base, q0, goals, mix_seed(seed, 1000000 + std::uint64_t(current_attempt)));
}

ArmMove Mission::Impl::move(const motion::PlanResult& plan, const nbv::PlannedView& view,
                            const sim::SimState& before, PhaseTimes& times) {
  ScopedPhase phase_time(times, to_string(WallPhase::kControl));
  return move_arm(stepper, model, plan.trajectory, view.T_world_camera, settings.motion.execution, &truth_checker,
                  before);
}

void Mission::Impl::leave_collision(const motion::PlanResult& plan, const nbv::PlannedView& view, PhaseTimes& times) {
  if (!plan.repaired || plan.repair.size() < 2) return;
  motion::PlanResult leave;
  leave.trajectory = planner.repair_trajectory(plan);
  nbv::PlannedView to = view;
  to.T_world_camera = model.camera_pose(sim.base_pose(), plan.repair.back());
  const ArmMove moved = move(leave, to, sim.snapshot(), times);
  if (!moved.diverged.empty()) ++result.unstable_faults;
}

Mission::Impl::Look Mission::Impl::take_look(PhaseTimes& times) {
  Look look;
  {
    ScopedPhase phase_time(times, to_string(WallPhase::kRendering));
    look.frame = renderer.render_wrist_camera();
  }
  ScopedPhase phase_time(times, to_string(WallPhase::kMapping));
  look.cloud = extractor.extract(look.frame, &look.mapped_labels);
  return look;
}

ViewRecord Mission::Impl::attempt(const nbv::PlannedView& view, ViewPhase phase) {
  ViewRecord rec = open_record(view, phase);
  const BasePose base = sim.base_pose();
  const ArmConfig q0 = sim.arm_positions();
  auto finish = [&](FailureCause cause, const std::string& message) { return close_record(rec, cause, message); };

  // Motion planning: IK, then OMPL against the map.
  motion::PlanResult plan;
  std::vector<ArmConfig> goals;
  bool overlap = false;
  {
    ScopedPhase phase_time(rec.times, to_string(WallPhase::kMotionPlanning));
    goals = motion::view_goal_configs(model, view, base, q0);
    if (goals.empty()) return finish(FailureCause::kNoIk, "no IK solution within the joint limits");
    // An overlapped move is only ever a straight one: without one, no search is run before the
    // scan is in (a search's plan would be dropped and made again, and an unreachable view
    // would use up its budget twice).
    std::optional<motion::PlanResult> straight;
    if (may_overlap()) straight = straight_move(base, q0, goals);
    overlap = straight.has_value();
    if (overlap) {
      plan = std::move(*straight);
    } else {
      scans.follow();
      plan = plan_move(base, q0, goals);
    }
  }
  rec.start_repair = plan.repaired ? plan.repair_note : "";
  rec.plan_iterations = plan.iterations;
  if (!plan.ok()) {
    leave_collision(plan, view, rec.times);
    return finish(failure_of_plan(plan.status), plan.message);
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
      ScopedPhase phase_time(rec.times, to_string(WallPhase::kMotionPlanning));
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
      rec.plan_iterations = plan.iterations;
      if (!plan.ok()) {
        leave_collision(plan, view, rec.times);
        return finish(failure_of_plan(plan.status), plan.message);
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
    return finish(FailureCause::kUnstable, moved.diverged);
  }
  const motion::MoveReport& report = moved.report;
  rec.move_time_s = report.duration_s;
  rec.truth_contacts = report.truth_contact_checks;
  rec.self_contacts = report.self_contact_steps;
  rec.position_error_m = report.position_error_m;
  rec.angle_error_rad = report.angle_error_rad;
  if (!report.success) return finish(FailureCause::kNotReached, report.message);

  if (!look) look = take_look(rec.times);
  const LabelledFrame& frame = look->frame;
  rec.T_reached = frame.T_world_camera;
  rec.target_points = static_cast<long>(look->cloud.stats.target_points);
  rec.true_target_pixels = static_cast<long>(look->cloud.stats.true_target_pixels);
  // The insertion, the NBV index and the metrics on the second core beside the next move
  // (scan_pipeline.h), the planner's environment before it plans.
  {
    ScopedPhase phase_time(rec.times, to_string(WallPhase::kMapping));
    settle();  // the last scan's mapping ends before the map changes
    hold_map_near(current_stop, false);  // (idle now)
    if (callbacks.replay) {
      callbacks.replay->record_frame(frame, &look->mapped_labels);
      const sim::RobotLinks robot = sim.robot_links();
      callbacks.replay->record_robot(robot.links, robot.parents, robot.poses);
    }
    scans.start(std::move(look->cloud), settings.mission.record.metrics_every_view);
    background_view_ = result.views.size();  // the row this record will take
  }
  for_each_planner([&](nbv::ViewPlanner& p) { p.taken(frame.T_world_camera); });
  close_record(rec, FailureCause::kNone, "camera within tolerance");
  if (callbacks.on_view) {
    scans.follow();  // the callback may read the map
    callbacks.on_view(rec, frame, sim);
  }
  update_caption();
  return rec;
}

void Mission::Impl::record(const ViewRecord& v, const nbv::PlannedView& view) {
  result.views.push_back(v);
  ok_views_ += v.success;
  StopRecord& s = stop_record();
  s.count(v);
  s.start_repairs += !v.start_repair.empty();
  if (!scans.busy()) report(v);  // else once its metrics are known (settle)
  nbv::ViewOutcome o;
  o.view = view;
  o.success = v.success;
  o.failure = to_string(v.failure);
  o.detail = v.start_repair.empty() ? v.message : v.message + " (start repaired: " + v.start_repair + ")";
  o.T_reached = v.T_reached;
  o.stop = v.stop;
  o.attempt = v.attempt;
  o.phase = to_string(v.phase);
  o.start_repaired = !v.start_repair.empty();
  for_each_planner([&](nbv::ViewPlanner& p) { p.outcome(o); });
  if (nbv::joins_failed_views(o) && !failed_here.contains(view.T_world_camera)) failed_here.add(view.T_world_camera);
}

void Mission::Impl::clear_robot_volume() {
  map_env->clear_robot_volume(model, sim.base_pose(), sim.arm_positions(), settings.motion.collision.environment_padding_m);
}

void Mission::Impl::report(const ViewRecord& v) const {
  progress(progress_line(v, static_cast<int>(stops_x.size()), elapsed_.seconds()));
}

}  // namespace canopy::mission
