#pragma once
// The robot's frames as a transform tree, for recordings of a mission (ROS bags, MCAP): every
// URDF link the simulator keeps a frame of, with its nearest such ancestor ("world" at the
// root) and whether the edge between them is fixed (only fixed joints: /tf_static) or moves.

#include <string>
#include <vector>

#include "canopy/common/types.h"
#include "canopy/robot/robot_description.h"
#include "canopy/sim/simulator.h"

namespace canopy::jobs {

/// The name of the tree's root frame in every recording canopy writes.
constexpr const char* kWorldFrame = "world";

/// The robot's frames, parents first.
struct RobotFrames {
  std::vector<std::string> names;    ///< Links with a frame in the simulator.
  std::vector<std::string> parents;  ///< Each one's nearest ancestor with a frame; kWorldFrame at the root.
  std::vector<bool> fixed;           ///< The edge to the parent passes through fixed joints only.

  /// Reads the tree of `sim`'s robot (its URDF and the frames the scene keeps).
  static RobotFrames of(const sim::Simulator& sim);
  /// Every frame's world pose now, in `names`' order.
  std::vector<Pose> world_poses(const sim::Simulator& sim) const;
};

}  // namespace canopy::jobs
