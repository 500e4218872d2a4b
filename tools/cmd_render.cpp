// canopy render: render one view of a world from the wrist camera or a free camera.

#include <spdlog/spdlog.h>

#include <optional>

#include "canopy/common/error.h"
#include "canopy/datasets/frame_io.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/value_text.h"
#include "canopy/motion/robot_model.h"
#include "canopy/sim/renderer.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_render_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string base, joints, camera_pose, out;
    bool shadows = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "render", "Render one view: rgb.png, depth.png (16-bit mm), labels.png, instances.png, frame.json");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  auto* base = sub->add_option(
      "--base", opt->base,
      "Base pose x,y,yaw [m, m, rad] (default: on the aisle, the home camera facing the world's first plant)");
  auto* joints = sub->add_option("--joints", opt->joints, "Arm joints q1,...,q6 [rad] (default: home)");
  auto* pose = sub->add_option("--camera-pose", opt->camera_pose,
                               "Free camera pose x,y,z,qw,qx,qy,qz (optical frame: x right, y down, z forward); "
                               "renders without the robot");
  joints->excludes(pose);
  base->excludes(pose);  // the free camera hides the robot: a base pose would be ignored
  sub->add_flag("--shadows", opt->shadows, "Shadows in the RGB image");
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->callback([opt] {
    // Validate every input before doing any work.
    world::WorldSpec spec = jobs::load_world_spec(opt->world);
    std::optional<BasePose> base_pose;
    if (!opt->base.empty()) base_pose = parse_base_pose(opt->base, "--base");
    RobotConfig robot_config = default_robot_config();
    ArmConfig q = robot_config.home;
    if (!opt->joints.empty()) {
      const auto v = parse_numbers(opt->joints, kArmDof, "--joints");
      std::copy(v.begin(), v.end(), q.begin());
      if (!motion::RobotModel::load(robot_config).within_limits(q))
        throw InputError("--joints: value '" + opt->joints + "' is outside the joint limits");
    }
    Pose T_world_camera = Pose::Identity();
    const bool free_camera = !opt->camera_pose.empty();
    if (free_camera) T_world_camera = parse_pose7(opt->camera_pose, "--camera-pose");

    StagedDir out(opt->out, "render");

    const world::World world = jobs::build_world(spec);
    sim::Simulator sim(world, robot_config);
    if (!base_pose) {
      // The world's robot_start sees no plant; put the home camera in front of the first one.
      sim.set_robot_state(BasePose{0.0, 0.0, 0.0}, q);
      base_pose = BasePose{world.plants.front().base_position.x() - sim.camera_pose().translation().x(), 0.0, 0.0};
    }
    sim.set_robot_state(*base_pose, q);
    sim::RenderOptions render_options;
    render_options.shadows = opt->shadows;
    sim::Renderer renderer(sim, spec.camera, render_options);
    const LabelledFrame frame = free_camera ? renderer.render_free_camera(T_world_camera) : renderer.render_wrist_camera();
    datasets::write_frame(out.path(""), frame, spec.classes);
    YAML::Node run = jobs::run_record("render", spec);
    run["shadows"] = opt->shadows;
    if (free_camera) {
      run["camera_pose"] = YAML::Load(pose_to_json(T_world_camera).dump());
    } else {
      run["base"] = std::vector<double>{base_pose->x_m, base_pose->y_m, base_pose->yaw_rad};
      run["joints"] = std::vector<double>(q.begin(), q.end());
    }
    write_file_atomic(out.path("run.yaml"), yaml_text(run));
    out.commit();
    int valid = 0;
    for (float z : frame.depth_m.data) valid += z > 0.f;
    spdlog::info("wrote {}/rgb.png depth.png labels.png instances.png frame.json ({} of {} depth pixels valid)",
                 opt->out, valid, frame.depth_m.data.size());
  });
}

}  // namespace canopy::cli
