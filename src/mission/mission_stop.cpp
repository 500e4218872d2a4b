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
  bool cleared = false;
  req.reachable = [&](const nbv::PlannedView& v) {
    ScopedPhase t(result.times, to_string(WallPhase::kNbvPlanning));
    if (!cleared) clear_robot_volume();  // the arm has not moved since: once is enough
    cleared = true;
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
  req.failed = &failed_here;
  const nbv::PlannerTraits traits = view_planner->traits();
  if (traits.scripted) req.scripted = scan_views(k, true);
  const motion::StopArm arm{model, workspace, &planner.goal_checker(), settings.motion.tour};
  // One planning round of `p` on the latest map (its times in the mission's phases).
  auto plan_round = [&](nbv::ViewPlanner& p, std::uint64_t round_seed, bool audited) {
    const Stopwatch watch;
    req.seed = round_seed;
    req.on_scored = audited && audit ? audit->observer() : nbv::CandidateObserver{};
    motion::NextViews next = motion::next_views(map, index, p, arm, req);
    result.times.merge(next.batch.times);
    // The planner's own phases are in batch.times; the rest (tour, bookkeeping) here.
    result.times.add(to_string(WallPhase::kNbvPlanning), std::max(0.0, watch.seconds() - next.batch.times.total()));
    s.guarded += static_cast<int>(next.guarded);
    return next;
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
    scans.follow_index();  // the last scan in the map and the index; its metrics may come later
    hold_map_near(k, true);  // a stop without a scan yet: the map near it before the planner reads it
    // A long row's index holds the bricks near the stop (issue 49; the others are read from the
    // map). The pipeline's thread is past the index (follow_index), so it may change here.
    if (const double near = near_robot_m(); near > 0.0)
      index.keep_x(map, stops_x[static_cast<std::size_t>(k)] - near, stops_x[static_cast<std::size_t>(k)] + near);
    req.base = sim.base_pose();
    req.q = sim.arm_positions();
    // The camera where the arm is now: after a drive and a stop without a successful view nothing
    // has rendered (which updates the kinematics) since the last step, and a render in between
    // (the candidate audit's) must not change what the planner is given. (The robot model's pose,
    // model.camera_pose(base, q), differs from MuJoCo's in the last digits: it would change views.)
    sim.update_kinematics();
    req.T_world_camera = sim.camera_pose();
    req.budget = wanted_total - ok;
    req.max_views = static_cast<std::size_t>(attempts_left);
    {
      // Every use of the collision environment at planning sees it without the robot's volume.
      ScopedPhase t(result.times, to_string(WallPhase::kNbvPlanning));
      clear_robot_volume();
    }
    const std::uint64_t round_seed = mix_seed(seed, 5000 + std::uint64_t(k) * 1000 + std::uint64_t(s.rounds));
    motion::NextViews next = plan_round(*view_planner, round_seed, true);
    check_stop();  // a stop requested while the planner ran (a Python planner's KeyboardInterrupt) wins
    if (audit) {
      ScopedPhase t(result.times, to_string(WallPhase::kEvaluation));
      audit->end_round(map, index, next.batch, k, s.rounds, ok_views_, round_seed, req.region, *req.T_world_camera);
    }
    ++s.rounds;
    s.refused += static_cast<int>(next.batch.refused.size());
    bool explored = false;
    if (next.batch.views.empty() && next.batch.refused.empty() && exploration_planner) {
      // The method has nothing to attempt (it is done with the stop, or offered only views that
      // failed here): the exploration planner's views fill the round, and the method plans
      // again first the next round. The stop's budget is the mission's to keep, not the method's.
      motion::NextViews fill = plan_round(*exploration_planner, mix_seed(round_seed, 1), false);
      check_stop();
      if (!fill.batch.views.empty()) {
        ++s.exploration_rounds;
        fill.batch.last_of_stop = false;
        next = std::move(fill);
        explored = true;
      } else if (!next.batch.finished || fill.batch.finished) {
        next.batch.finished = next.batch.finished && fill.batch.finished;
        next.batch.reason += (next.batch.reason.empty() ? "" : "; ") + std::string("exploration (") +
                             loop.exploration + "): " + (fill.batch.reason.empty() ? "nothing" : fill.batch.reason);
      } else {
        next.batch.finished = false;  // the exploration planner may find views next round
        next.batch.reason += "; exploration (" + loop.exploration + "): " + (fill.batch.reason.empty() ? "nothing" : fill.batch.reason);
      }
    }
    const nbv::ViewBatch& batch = next.batch;
    const std::vector<nbv::PlannedView>& ordered = next.ordered;
    const std::vector<nbv::PlannedView>& unreachable = next.unreachable;
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
    const ViewPhase phase = traits.scripted && !explored ? ViewPhase::kPredefined : ViewPhase::kNbv;
    record_unreachable(unreachable, phase, &attempts_left);
    const int wanted = wanted_total - ok;
    if (batch.order == nbv::BatchOrder::kTour) {
      std::vector<nbv::PlannedView> failed = unreachable;
      failed.insert(failed.end(), batch.refused.begin(), batch.refused.end());  // not attempts
      const bool whole = !explored && traits.execute_whole_batch;
      ok += execute(ordered, phase, whole ? -1 : wanted, &attempts_left, &failed);
      if (!explored && replaces_failed_scripted()) ok += replace_failed(failed, phase, &attempts_left);
    } else {
      ok += execute(ordered, phase, 1, &attempts_left);  // frontier: the first view that succeeds
    }
    // A planner's last batch ends the stop unless the exploration planner is to fill its budget.
    if (batch.last_of_stop && (ok >= wanted_total || !exploration_planner)) {
      if (ok >= wanted_total) end_stop(s, "budget_met", "view budget of the stop reached");
      else end_stop(s, "planner_done", "the planner has nothing left to see: " + batch.reason);
      break;
    }
  }
}

}  // namespace canopy::mission
