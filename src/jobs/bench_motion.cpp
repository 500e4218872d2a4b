#include "canopy/jobs/bench_motion.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/random.h"
#include "canopy/common/timer.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/jobs/world_job.h"
#include "canopy/motion/reachability.h"

namespace canopy::jobs {

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5))];
}

}  // namespace

nlohmann::json BenchMotionResult::to_json() const {
  nlohmann::json j;
  j["ik_us_per_solve"] = ik_us;
  j["camera_ik_us_per_solve"] = camera_ik_us;
  j["fk_us_per_call"] = fk_us;
  j["ik_solutions_per_pose"] = ik_solutions_per_pose;
  j["validity_us_per_state"] = validity_us;
  j["validity_free_us_per_state"] = validity_free_us;
  j["map_voxels"] = map_voxels;
  j["planner"] = planner;
  j["planning_goals"] = goals;
  j["planning_success_rate"] = goals ? double(planned) / goals : 0.0;
  j["planning_direct"] = direct;
  j["planning_median_s"] = median_s;
  j["planning_p90_s"] = p90_s;
  j["planning_max_s"] = max_s;
  j["planning_statuses"] = statuses;
  j["motion_config"] = motion_config;
  return j;
}

BenchMotionResult bench_motion(const BenchMotionParams& p) {
  const world::WorldSpec spec = load_world_spec(p.world_file);
  const RobotConfig robot = default_robot_config();
  const motion::MotionConfig& cfg = p.motion;
  const motion::RobotModel model = motion::RobotModel::load(robot);
  motion::seed_planner_rng(cfg.seed);
  Rng rng(p.seed);
  auto random_q = [&] {
    ArmConfig q;
    for (auto& v : q) v = rng.uniform(-M_PI, M_PI);
    return q;
  };
  BenchMotionResult r;
  r.planner = cfg.planner.planner;
  r.time_limit_s = cfg.planner.time_limit_s;
  r.motion_config = params_to_json(cfg);

  // 1. Kinematics on random poses of random configurations.
  std::vector<Pose> poses06(static_cast<size_t>(p.ik_poses)), poses_cam(poses06.size());
  std::vector<ArmConfig> seeds(poses06.size());
  for (size_t i = 0; i < poses06.size(); ++i) {
    const ArmConfig q = random_q();
    poses06[i] = model.ur().fk(q);
    poses_cam[i] = poses06[i] * model.T_tool_camera();
    seeds[i] = random_q();
  }
  long solutions = 0;
  Stopwatch watch;
  for (const Pose& T : poses06) solutions += model.ur().ik(T).count;
  r.ik_us = (1e6 * watch.seconds()) / static_cast<double>(poses06.size());
  long filtered = 0;
  watch.restart();
  for (size_t i = 0; i < poses_cam.size(); ++i) filtered += model.camera_ik_in_arm(poses_cam[i], seeds[i]).count;
  r.camera_ik_us = (1e6 * watch.seconds()) / static_cast<double>(poses_cam.size());
  watch.restart();
  for (const ArmConfig& q : seeds) r.fk_checksum += model.ur().fk(q).translation().x();
  r.fk_us = (1e6 * watch.seconds()) / static_cast<double>(seeds.size());
  r.ik_solutions_per_pose = double(solutions) / double(poses06.size());
  r.camera_ik_solutions_per_pose = double(filtered) / double(poses_cam.size());

  // 2. Validity checks against the world's occupancy (a fully observed map).
  const world::World world = build_world(spec);
  const std::vector<Vec3> voxels = evaluation::world_occupied_voxels(world, r.map_resolution_m);
  r.map_voxels = voxels.size();
  const motion::CollisionChecker checker(model, cfg.collision,
                                         motion::CollisionEnvironment::from_voxels(voxels, r.map_resolution_m));
  std::vector<ArmConfig> states(static_cast<size_t>(p.states));
  for (auto& q : states) q = random_q();
  std::vector<char> colliding(states.size());
  watch.restart();
  for (size_t i = 0; i < states.size(); ++i)
    colliding[i] = checker.in_collision(p.base, states[i], motion::BodySet::kArmOnly);
  r.validity_us = (1e6 * watch.seconds()) / static_cast<double>(states.size());
  std::vector<ArmConfig> free_states;
  for (size_t i = 0; i < states.size(); ++i)
    if (!colliding[i]) free_states.push_back(states[i]);
  watch.restart();
  for (const ArmConfig& q : free_states) r.free_states_colliding += checker.in_collision(p.base, q, motion::BodySet::kArmOnly);
  r.validity_free_us = free_states.empty() ? 0.0 : (1e6 * watch.seconds()) / static_cast<double>(free_states.size());
  r.colliding_fraction = double(states.size() - free_states.size()) / double(states.size());

  // 3. Planning from home to random reachable goals (camera poses of random collision-free
  //    configurations, all IK branches offered to the planner).
  const motion::ArmPlanner planner(checker, cfg.planner, cfg.trajectory);
  std::vector<double> times;
  while (r.goals < p.goals) {
    const ArmConfig q = random_q();
    if (checker.in_collision(p.base, q)) continue;
    const Pose goal = model.camera_pose(p.base, q);
    ++r.goals;
    const motion::PlanResult plan = planner.plan_to_camera_pose(p.base, robot.home, goal);
    ++r.statuses[motion::to_string(plan.status)];
    if (plan.ok()) {
      ++r.planned;
      r.direct += plan.direct;
      times.push_back(plan.planning_time_s);
    }
  }
  r.median_s = percentile(times, 0.5);
  r.p90_s = percentile(times, 0.9);
  r.max_s = percentile(times, 1.0);
  return r;
}

}  // namespace canopy::jobs
