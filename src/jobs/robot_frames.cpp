#include "canopy/jobs/robot_frames.h"

#include "canopy/common/error.h"

namespace canopy::jobs {

RobotFrames RobotFrames::of(const sim::Simulator& sim) {
  const robot::RobotDescription d = robot::RobotDescription::load_urdf(sim.robot_config().urdf_path);
  RobotFrames t;
  const std::size_t n = d.links().size();
  std::vector<std::string> frame_of(n, kWorldFrame);  // a link's nearest ancestor (or itself) with a frame
  std::vector<bool> fixed_to_frame(n, true);          // only fixed joints between the link and frame_of
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& name = d.links()[i].name;
    const int parent = d.parent_link(static_cast<int>(i));
    const std::string above = parent < 0 ? kWorldFrame : frame_of[static_cast<std::size_t>(parent)];
    const int joint = d.links()[i].parent_joint;
    const bool joint_fixed = joint < 0 || !d.joints()[static_cast<std::size_t>(joint)].movable();
    // Fixed down from `above`: the parent's own path to `above` and this link's joint.
    const bool fixed = joint_fixed && (parent < 0 || fixed_to_frame[static_cast<std::size_t>(parent)]);
    bool has_frame = name != kWorldFrame;
    if (has_frame) {
      try {
        (void)sim.frame_pose(name);
      } catch (const InputError&) {  // a link the scene keeps no frame of
        has_frame = false;
      }
    }
    frame_of[i] = has_frame ? name : above;
    fixed_to_frame[i] = has_frame ? true : fixed;
    if (!has_frame) continue;
    t.names.push_back(name);
    t.parents.push_back(above);
    t.fixed.push_back(fixed);
  }
  return t;
}

std::vector<Pose> RobotFrames::world_poses(const sim::Simulator& sim) const {
  std::vector<Pose> poses;
  poses.reserve(names.size());
  for (const std::string& name : names) poses.push_back(sim.frame_pose(name));
  return poses;
}

}  // namespace canopy::jobs
