// canopy reach: which camera views around the plants the arm can reach from one base pose:
// IK-reachable, collision-free and planned fractions (reach.json) and a map (reach.png).

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/png_io.h"
#include "canopy/common/value_text.h"
#include "canopy/motion/motion_config.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/motion/reachability.h"
#include "canopy/world/world.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

// Colours of the map (also written into reach.json).
const Rgb8 kNoIk{215, 60, 50}, kInCollision{245, 160, 30}, kPlanFailed{60, 110, 220}, kPlanned{30, 160, 60};
const Rgb8 kPlant{165, 210, 150}, kRobot{120, 120, 120}, kTarget{0, 0, 0};

// Two panels side by side: top view (x right, y up) and side view from behind the base's
// aisle direction (lateral axis right, z up), both centred on the arm base.
class MapImage {
 public:
  MapImage(const Vec3& centre, double half_width_m, int panel_px)
      : c_(centre), half_(half_width_m), n_(panel_px), img_(2 * panel_px + 4, panel_px, Rgb8{255, 255, 255}) {
    for (int y = 0; y < n_; ++y)
      for (int x = n_; x < n_ + 4; ++x) img_.at(x, y) = Rgb8{200, 200, 200};
  }
  void dot(const Vec3& p, const Rgb8& colour, int radius) {
    plot(0, p.x() - c_.x(), p.y() - c_.y(), colour, radius);
    plot(n_ + 4, p.y() - c_.y(), p.z() - c_.z(), colour, radius);
  }
  const Image<Rgb8>& image() const { return img_; }

 private:
  void plot(int x0, double u, double v, const Rgb8& colour, int r) {
    const int px = static_cast<int>(std::lround((u + half_) / (2 * half_) * (n_ - 1)));
    const int py = static_cast<int>(std::lround((half_ - v) / (2 * half_) * (n_ - 1)));
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int x = px + dx, y = py + dy;
        if (x >= 0 && x < n_ && y >= 0 && y < n_ && dx * dx + dy * dy <= r * r) img_.at(x0 + x, y) = colour;
      }
  }
  Vec3 c_;
  double half_;
  int n_;
  Image<Rgb8> img_;
};

nlohmann::json rgb_json(const Rgb8& c) { return {c.r, c.g, c.b}; }

}  // namespace

void add_reach_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string config = settings::default_settings_path();
    std::string base, joints, out;
    motion::ReachParams grid;
    double voxel_m = 0.015;
    bool no_plan = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "reach", "Reachability of camera views around the plants from one base pose: reach.json, reach.png");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--base", opt->base, "Base pose x,y,yaw [m, m, rad]")->required();
  sub->add_option("--joints", opt->joints, "Start arm joints q1,...,q6 [rad] (default: home)");
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--radius", opt->grid.sphere.radius_m, "Camera distance to each fruit [m]")->capture_default_str();
  sub->add_option("--azimuths", opt->grid.sphere.azimuth_count, "Viewing azimuths per fruit")->capture_default_str();
  sub->add_option("--polar", opt->grid.sphere.polar_count, "Polar angles per fruit, 30..150 deg")->capture_default_str();
  sub->add_option("--max-target-distance", opt->grid.max_target_distance_m,
                  "Fruits farther from the arm base (horizontally) are skipped [m]")
      ->capture_default_str();
  sub->add_option("--voxel", opt->voxel_m, "Voxel size of the world's occupancy used for collisions [m]")
      ->capture_default_str();
  sub->add_flag("--no-plan", opt->no_plan, "IK and collisions only (no motion planning)");
  sub->callback([opt] {
    // Validate every input before doing any work.
    const world::WorldSpec spec = jobs::load_world_spec(opt->world);
    const RobotConfig robot = default_robot_config();
    const motion::MotionConfig cfg = load_settings(opt->config).motion;
    const BasePose base = parse_base_pose(opt->base, "--base");
    ArmConfig start = robot.home;
    if (!opt->joints.empty()) {
      const auto v = parse_numbers(opt->joints, kArmDof, "--joints");
      std::copy(v.begin(), v.end(), start.begin());
    }
    motion::ReachParams grid = opt->grid;
    grid.plan = !opt->no_plan;
    grid.validate();
    if (!(std::isfinite(opt->voxel_m) && opt->voxel_m >= 0.002 && opt->voxel_m <= 0.2))
      throw InputError("--voxel " + std::to_string(opt->voxel_m) + " must be in [0.002, 0.2] m");
    const motion::RobotModel model = motion::RobotModel::load(robot);
    if (!model.within_limits(start)) throw InputError("--joints: outside the joint limits");

    motion::seed_planner_rng(cfg.seed);
    const world::World world = jobs::build_world(spec);
    const std::vector<Vec3> voxels = evaluation::world_occupied_voxels(world, opt->voxel_m);
    const motion::CollisionChecker checker(model, cfg.collision,
                                           motion::CollisionEnvironment::from_voxels(voxels, opt->voxel_m));
    const motion::ArmPlanner planner(checker, cfg.planner, cfg.trajectory);
    const motion::WorkspaceFilter filter(model, cfg.workspace);
    if (checker.in_collision(base, start))
      spdlog::warn("the start state is in collision at this base pose: {}", checker.report(base, start).pairs.front());
    const motion::ReachReport report =
        motion::evaluate_reachability(planner, &filter, base, start, evaluation::world_fruit_centres(world), grid);

    // The map: plants, robot footprint, views coloured by outcome (best on top).
    const Vec3 arm = (motion::RobotModel::T_world_base(base) * model.T_base_arm()).translation();
    MapImage map(arm, 1.3, 520);
    for (const Vec3& v : voxels)
      if ((v - arm).head<2>().norm() < 1.9) map.dot(v, kPlant, 0);
    // Outline of the top face of every box-shaped robot body (chassis, mast, camera).
    std::vector<Pose> body_poses;
    model.body_poses(base, start, &body_poses);
    for (size_t b = 0; b < model.bodies().size(); ++b) {
      const robot::Shape& shape = model.bodies()[b].shape;
      if (shape.type != robot::ShapeType::kBox) continue;
      const Vec3 h = 0.5 * shape.box_size;
      for (double u = -1.0; u <= 1.0; u += 0.01)
        for (double side : {-1.0, 1.0}) {
          map.dot(body_poses[b] * Vec3(u * h.x(), side * h.y(), h.z()), kRobot, 0);
          map.dot(body_poses[b] * Vec3(side * h.x(), u * h.y(), h.z()), kRobot, 0);
        }
    }
    map.dot(arm, kRobot, 3);
    for (int pass = 0; pass < 4; ++pass)
      for (const auto& s : report.samples) {
        const int cls = s.planned ? 3 : s.collision_free ? 2 : s.ik ? 1 : 0;
        if (cls != pass) continue;
        const Rgb8 colours[] = {kNoIk, kInCollision, kPlanFailed, kPlanned};
        map.dot(s.T_world_camera.translation(), colours[cls], cls == 0 ? 1 : 2);
      }
    for (const auto& s : report.samples) map.dot(s.target, kTarget, 1);

    nlohmann::json j = report.to_json(true);
    j["world"] = spec.name;
    j["world_file"] = opt->world;
    j["start_joints"] = start;
    j["grid"] = yaml_to_json(params_to_yaml(grid));
    j["environment"] = {{"source", "ground-truth plant meshes voxelised"},
                        {"voxel_m", opt->voxel_m},
                        {"voxels", voxels.size()}};
    j["motion_config"] = yaml_to_json(params_to_yaml(cfg));
    j["png"] = {{"panels", "left: top view (x right, y up); right: side view (y right, z up); 2.6 m wide, "
                           "centred on the arm base"},
                {"no_ik", rgb_json(kNoIk)},
                {"ik_but_in_collision", rgb_json(kInCollision)},
                {"collision_free_plan_failed", rgb_json(kPlanFailed)},
                {"planned", rgb_json(kPlanned)},
                {"plants", rgb_json(kPlant)},
                {"robot", rgb_json(kRobot)},
                {"targets", rgb_json(kTarget)}};
    StagedDir out(opt->out, "reach");
    write_json_atomic(out.path("reach.json"), j);
    write_png(out.path("reach.png"), map.image());
    out.commit();
    std::printf("base %.3f,%.3f,%.3f: %d fruits, %zu views: IK-reachable %.3f, collision-free %.3f, planned %.3f, "
                "workspace filter kept %.3f (median planning %.1f ms)\n",
                base.x_m, base.y_m, base.yaw_rad, report.targets, report.samples.size(), report.fraction_ik(),
                report.fraction_collision_free(), report.fraction_planned(),
                report.samples.empty() ? 0.0 : double(report.count_workspace_kept()) / report.samples.size(),
                1e3 * report.median_planning_time_s());
    spdlog::info("wrote {}/reach.json and reach.png", opt->out);
  });
}

}  // namespace canopy::cli
