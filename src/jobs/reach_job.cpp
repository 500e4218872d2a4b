#include "canopy/jobs/reach_job.h"

#include <cmath>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/png_io.h"
#include "canopy/evaluation/truth_voxels.h"
#include "canopy/jobs/world_job.h"

namespace canopy::jobs {

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

ArmConfig checked_start(const motion::RobotModel& model, const ReachJobParams& p) {
  if (!p.joints) return model.config().home;
  if (!model.within_limits(*p.joints)) throw InputError(p.joints_where + ": outside the joint limits");
  return *p.joints;
}

}  // namespace

Image<Rgb8> reach_map(const motion::ReachReport& report, const motion::RobotModel& model, const ArmConfig& start,
                      const std::vector<Vec3>& plant_voxels, nlohmann::json* legend) {
  const Vec3 arm = (motion::RobotModel::T_world_base(report.base) * model.T_base_arm()).translation();
  MapImage map(arm, 1.3, 520);
  for (const Vec3& v : plant_voxels)
    if ((v - arm).head<2>().norm() < 1.9) map.dot(v, kPlant, 0);
  // Outline of the top face of every box-shaped robot body (chassis, mast, camera).
  std::vector<Pose> body_poses;
  model.body_poses(report.base, start, &body_poses);
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
  const Rgb8 colours[] = {kNoIk, kInCollision, kPlanFailed, kPlanned};
  for (int pass = 0; pass < 4; ++pass)
    for (const auto& s : report.samples) {
      const int cls = s.planned ? 3 : s.collision_free ? 2 : s.ik ? 1 : 0;
      if (cls == pass) map.dot(s.T_world_camera.translation(), colours[cls], cls == 0 ? 1 : 2);
    }
  for (const auto& s : report.samples) map.dot(s.target, kTarget, 1);
  if (legend)
    *legend = {{"panels", "left: top view (x right, y up); right: side view (y right, z up); 2.6 m wide, "
                          "centred on the arm base"},
               {"no_ik", rgb_json(kNoIk)},
               {"ik_but_in_collision", rgb_json(kInCollision)},
               {"collision_free_plan_failed", rgb_json(kPlanFailed)},
               {"planned", rgb_json(kPlanned)},
               {"plants", rgb_json(kPlant)},
               {"robot", rgb_json(kRobot)},
               {"targets", rgb_json(kTarget)}};
  return map.image();
}

ReachJobResult reach(const ReachJobParams& p) {
  // Validate every input before doing any work.
  const world::WorldSpec spec = load_world_spec(p.world_file);
  motion::ReachParams grid = p.grid;
  grid.validate();
  if (!(std::isfinite(p.voxel_m) && p.voxel_m >= 0.002 && p.voxel_m <= 0.2))
    throw InputError("--voxel " + params_detail::shortest(p.voxel_m) + " must be in [0.002, 0.2] m");
  const motion::RobotModel model = motion::RobotModel::load(default_robot_config());
  const ArmConfig start = checked_start(model, p);

  motion::seed_planner_rng(p.motion.seed);
  const world::World world = build_world(spec);
  const std::vector<Vec3> voxels = evaluation::world_occupied_voxels(world, p.voxel_m);
  const motion::CollisionChecker checker(model, p.motion.collision,
                                         motion::CollisionEnvironment::from_voxels(voxels, p.voxel_m));
  const motion::ArmPlanner planner(checker, p.motion.planner, p.motion.trajectory);
  const motion::WorkspaceFilter filter(model, p.motion.workspace);
  ReachJobResult r;
  if (checker.in_collision(p.base, start)) r.start_collision = checker.report(p.base, start).pairs.front();
  r.report = motion::evaluate_reachability(planner, &filter, p.base, start, evaluation::world_fruit_centres(world), grid);

  nlohmann::json legend;
  const Image<Rgb8> png = reach_map(r.report, model, start, voxels, &legend);
  nlohmann::json j = r.report.to_json(true);
  j["world"] = spec.name;
  j["world_file"] = p.world_file;
  j["start_joints"] = start;
  j["grid"] = params_to_json(grid);
  j["environment"] = {
      {"source", "ground-truth plant meshes voxelised"}, {"voxel_m", p.voxel_m}, {"voxels", voxels.size()}};
  j["motion_config"] = params_to_json(p.motion);
  j["png"] = legend;
  StagedDir out(p.out, "reach");
  write_json_atomic(out.path("reach.json"), j);
  write_png(out.path("reach.png"), png);
  out.commit();
  return r;
}

}  // namespace canopy::jobs
