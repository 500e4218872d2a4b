// canopy render: render one view of a world from the wrist camera or a free camera.

#include <spdlog/spdlog.h>

#include "canopy/common/error.h"
#include "canopy/common/frame_io.h"
#include "canopy/common/io.h"
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
  sub->add_option("--base", opt->base, "Base pose x,y,yaw [m, m, rad] (default: the world's robot_start)");
  auto* joints = sub->add_option("--joints", opt->joints, "Arm joints q1,...,q6 [rad] (default: home)");
  auto* pose = sub->add_option("--camera-pose", opt->camera_pose,
                               "Free camera pose x,y,z,qw,qx,qy,qz (optical frame: x right, y down, z forward); "
                               "renders without the robot");
  joints->excludes(pose);
  sub->add_flag("--shadows", opt->shadows, "Shadows in the RGB image");
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->callback([opt] {
    // Validate every input before doing any work.
    world::WorldSpec spec = load_world_spec(opt->world);
    if (!opt->base.empty()) spec.robot_start = parse_base_pose(opt->base, "--base");
    RobotConfig robot_config = default_robot_config();
    ArmConfig q = robot_config.home;
    if (!opt->joints.empty()) {
      const auto v = parse_numbers(opt->joints, kArmDof, "--joints");
      std::copy(v.begin(), v.end(), q.begin());
    }
    Pose T_world_camera = Pose::Identity();
    const bool free_camera = !opt->camera_pose.empty();
    if (free_camera) T_world_camera = parse_pose7(opt->camera_pose, "--camera-pose");

    const world::World world = world::generate_world(spec);
    sim::Simulator sim(world, robot_config);
    sim.set_robot_state(spec.robot_start, q);
    sim::RenderOptions render_options;
    render_options.shadows = opt->shadows;
    sim::Renderer renderer(sim, spec.camera, render_options);
    const LabelledFrame frame = free_camera ? renderer.render_free_camera(T_world_camera) : renderer.render_wrist_camera();
    StagedDir out(opt->out);
    write_frame(out.path(""), frame, spec.classes);
    out.commit();
    int valid = 0;
    for (float z : frame.depth_m.data) valid += z > 0.f;
    spdlog::info("wrote {}/rgb.png depth.png labels.png instances.png frame.json ({} of {} depth pixels valid)",
                 opt->out, valid, frame.depth_m.data.size());
  });
}

}  // namespace canopy::cli
