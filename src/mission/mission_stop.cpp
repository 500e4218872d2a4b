#include "mission_impl.h"

#include <algorithm>

#include "canopy/motion/reachability.h"
#include "canopy/motion/tour.h"
#include "canopy/motion/view_reach.h"

namespace canopy::mission {


std::vector<nbv::PlannedView> Mission::Impl::tour(std::vector<nbv::PlannedView> views,
                                                  std::vector<nbv::PlannedView>* unreachable) {
  return motion::tour_order(model, settings.motion.tour, sim.base_pose(), sim.arm_positions(), std::move(views),
                            unreachable);
}

int Mission::Impl::execute(const std::vector<nbv::PlannedView>& views, ViewPhase phase, int wanted,
                           int* attempts_left, std::vector<nbv::PlannedView>* failed) {
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

int Mission::Impl::replace_failed(const std::vector<nbv::PlannedView>& failed, ViewPhase phase, int* attempts_left) {
  const settings::ScanParams& scan = settings.mission.scan;
  const Pose T_world_base = motion::RobotModel::T_world_base(stop_pose(current_stop));
  std::vector<ScanView> pattern = scan_view_list(scan, world.spec, model.T_base_arm(), false);
  for (const ScanView& v : scan_view_list(scan, world.spec, model.T_base_arm(), true)) pattern.push_back(v);
  nbv::FailedScriptedView req;
  for (const ScanView& v : pattern) req.scripted.push_back(T_world_base * v.T_base_camera);
  req.max_attempts = scan.replace_max_attempts;
  req.attempts_left = attempts_left;
  req.reachable = [&](const nbv::PlannedView& v) {
    ScopedPhase t(result.times, to_string(WallPhase::kNbvPlanning));
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
      if (nbv::same_view(T_world_base * v.T_base_camera, f.T_world_camera)) spec = &v;
    if (!spec) continue;
    req.failed = f;
    req.options.clear();
    {
      ScopedPhase t(result.times, to_string(WallPhase::kNbvPlanning));
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

void Mission::Impl::record_unreachable(const std::vector<nbv::PlannedView>& views, ViewPhase phase,
                                       int* attempts_left) {
  for (const nbv::PlannedView& v : views) {
    if (attempts_left && *attempts_left <= 0) break;
    check_stop();
    if (attempts_left) --*attempts_left;
    ViewRecord r = open_record(v, phase);
    record(close_record(r, FailureCause::kNoIk, "no IK solution within the joint limits"), v);
  }
}

void Mission::Impl::scripted(const std::vector<Pose>& poses, ViewPhase phase) {
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
    ScopedPhase t(result.times, to_string(WallPhase::kNbvPlanning));
    ordered = tour(views, &unreachable);
  }
  record_unreachable(unreachable, phase);
  std::vector<nbv::PlannedView> failed = unreachable;
  execute(ordered, phase, -1, nullptr, &failed);
  if (replaces_failed_scripted()) replace_failed(failed, phase, nullptr);
}

void Mission::Impl::nbv_loop(int k, int scan_views_count) {
  const settings::LoopParams& loop = settings.mission.loop;
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
      result.times.add(to_string(WallPhase::kNbvPlanning), std::max(0.0, watch.seconds() - next.batch.times.total()));
    }
    check_stop();  // a stop requested while the planner ran (a Python planner's KeyboardInterrupt) wins
    const nbv::ViewBatch& batch = next.batch;
    if (audit) {
      ScopedPhase t(result.times, to_string(WallPhase::kEvaluation));
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

}  // namespace canopy::mission
