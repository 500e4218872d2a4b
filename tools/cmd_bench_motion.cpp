// canopy bench motion: IK time per solve, collision (validity) check time per state against
// the default world's occupancy, and planning success rate and times over random reachable
// goals (issue targets: IK <= 2 us, >= 95% success within 1 s each).

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "canopy/common/error.h"
#include "canopy/common/timer.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/random.h"
#include "canopy/motion/motion_config.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/motion/reachability.h"
#include "canopy/world/world.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {



double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5))];
}

}  // namespace

void add_bench_motion(CLI::App& bench) {
  struct Options {
    std::string world = default_world_path();
    std::string config = settings::default_settings_path();
    std::string base = "0.75,0,0";
    std::string json;
    int ik_poses = 100000;
    int states = 20000;
    int goals = 100;
    std::uint64_t seed = 7;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand("motion", "IK us/solve, validity check us/state, planning success and times");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--base", opt->base, "Base pose x,y,yaw for the collision and planning parts")->capture_default_str();
  sub->add_option("--ik-poses", opt->ik_poses, "Random poses for the IK timing")->capture_default_str()->check(CLI::Range(100, 10000000));
  sub->add_option("--states", opt->states, "Random states for the validity timing")->capture_default_str()->check(CLI::Range(100, 10000000));
  sub->add_option("--goals", opt->goals, "Random reachable goals to plan to")->capture_default_str()->check(CLI::Range(1, 100000));
  sub->add_option("--seed", opt->seed, "Seed of the random poses and goals")->capture_default_str();
  sub->add_option("--json", opt->json, "Also write the figures to this JSON file");
  sub->callback([opt] {
    const world::WorldSpec spec = jobs::load_world_spec(opt->world);
    const RobotConfig robot = default_robot_config();
    const motion::MotionConfig cfg = load_settings(opt->config).motion;
    const BasePose base = parse_base_pose(opt->base, "--base");
    const motion::RobotModel model = motion::RobotModel::load(robot);
    motion::seed_planner_rng(cfg.seed);
    Rng rng(opt->seed);
    auto random_q = [&] {
      ArmConfig q;
      for (auto& v : q) v = rng.uniform(-M_PI, M_PI);
      return q;
    };
    nlohmann::json j;

    // 1. Kinematics on random poses of random configurations.
    std::vector<Pose> poses06(static_cast<size_t>(opt->ik_poses)), poses_cam(poses06.size());
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
    const double ik_us = (1e6 * watch.seconds()) / static_cast<double>(poses06.size());
    long filtered = 0;
    watch.restart();
    for (size_t i = 0; i < poses_cam.size(); ++i) filtered += model.camera_ik_in_arm(poses_cam[i], seeds[i]).count;
    const double cam_ik_us = (1e6 * watch.seconds()) / static_cast<double>(poses_cam.size());
    double sink = 0.0;
    watch.restart();
    for (const ArmConfig& q : seeds) sink += model.ur().fk(q).translation().x();
    const double fk_us = (1e6 * watch.seconds()) / static_cast<double>(seeds.size());
    std::printf("kinematics (%d random poses)\n", opt->ik_poses);
    std::printf("  analytic IK, all branches         %8.3f us/solve  (%.2f solutions per pose)\n", ik_us,
                double(solutions) / poses06.size());
    std::printf("  camera IK: limits, 2pi, sorting   %8.3f us/solve  (%.2f solutions per pose)\n", cam_ik_us,
                double(filtered) / poses_cam.size());
    std::printf("  forward kinematics (DH frame 6)   %8.3f us/call   (checksum %.3f)\n", fk_us, sink);
    j["ik_us_per_solve"] = ik_us;
    j["camera_ik_us_per_solve"] = cam_ik_us;
    j["fk_us_per_call"] = fk_us;
    j["ik_solutions_per_pose"] = double(solutions) / poses06.size();

    // 2. Validity checks against the world's occupancy (a fully observed map).
    const world::World world = jobs::build_world(spec);
    const double res = 0.015;
    const std::vector<Vec3> voxels = evaluation::world_occupied_voxels(world, res);
    const motion::CollisionChecker checker(model, cfg.collision, motion::CollisionEnvironment::from_voxels(voxels, res));
    std::vector<ArmConfig> states(static_cast<size_t>(opt->states));
    for (auto& q : states) q = random_q();
    std::vector<char> colliding(states.size());
    watch.restart();
    for (size_t i = 0; i < states.size(); ++i) colliding[i] = checker.in_collision(base, states[i], motion::BodySet::kArmOnly);
    const double valid_us = (1e6 * watch.seconds()) / static_cast<double>(states.size());
    std::vector<ArmConfig> free_states;
    for (size_t i = 0; i < states.size(); ++i)
      if (!colliding[i]) free_states.push_back(states[i]);
    watch.restart();
    for (const ArmConfig& q : free_states) sink += checker.in_collision(base, q, motion::BodySet::kArmOnly);
    const double free_us = free_states.empty() ? 0.0 : (1e6 * watch.seconds()) / static_cast<double>(free_states.size());
    std::printf("validity checks (%zu occupied voxels of %.3f m, base %s)\n", voxels.size(), res, opt->base.c_str());
    std::printf("  random states                     %8.3f us/state  (%.1f%% in collision)\n", valid_us,
                100.0 * double(states.size() - free_states.size()) / states.size());
    std::printf("  collision-free states only        %8.3f us/state  (every pair and shape checked)\n", free_us);
    j["validity_us_per_state"] = valid_us;
    j["validity_free_us_per_state"] = free_us;
    j["map_voxels"] = voxels.size();

    // 3. Planning from home to random reachable goals (camera poses of random
    //    collision-free configurations, all IK branches offered to the planner).
    const motion::ArmPlanner planner(checker, cfg.planner, cfg.trajectory);
    std::vector<double> times, all_times;
    std::map<std::string, int> statuses;
    int ok = 0, direct = 0, attempts = 0;
    while (attempts < opt->goals) {
      const ArmConfig q = random_q();
      if (checker.in_collision(base, q)) continue;
      const Pose goal = model.camera_pose(base, q);
      ++attempts;
      const motion::PlanResult r = planner.plan_to_camera_pose(base, robot.home, goal);
      ++statuses[motion::to_string(r.status)];
      all_times.push_back(r.planning_time_s);
      if (r.ok()) {
        ++ok;
        direct += r.direct;
        times.push_back(r.planning_time_s);
      }
    }
    std::printf("planning (%s, %.2f s limit, %d random reachable goals from home)\n", cfg.planner.planner.c_str(),
                cfg.planner.time_limit_s, attempts);
    std::printf("  success rate                      %8.1f %%  (%d straight-line, %d via OMPL)\n",
                100.0 * ok / attempts, direct, ok - direct);
    std::printf("  time of successful plans          median %.1f ms, p90 %.1f ms, max %.1f ms\n",
                1e3 * percentile(times, 0.5), 1e3 * percentile(times, 0.9), 1e3 * percentile(times, 1.0));
    std::printf("  statuses:");
    for (const auto& [name, count] : statuses) std::printf(" %s %d", name.c_str(), count);
    std::printf("\n");
    j["planner"] = cfg.planner.planner;
    j["planning_goals"] = attempts;
    j["planning_success_rate"] = double(ok) / attempts;
    j["planning_direct"] = direct;
    j["planning_median_s"] = percentile(times, 0.5);
    j["planning_p90_s"] = percentile(times, 0.9);
    j["planning_max_s"] = percentile(times, 1.0);
    j["planning_statuses"] = statuses;
    j["motion_config"] = yaml_to_json(params_to_yaml(cfg));
    if (!opt->json.empty()) {
      write_json_atomic(opt->json, j);
      spdlog::info("wrote {}", opt->json);
    }
  });
}

}  // namespace canopy::cli
