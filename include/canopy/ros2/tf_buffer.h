#pragma once
// A recording's transform tree (/tf and /tf_static), read whole and looked up at any stamp as
// tf2 does: a sample at the stamp is taken as is, the two samples around it are interpolated
// (position linearly, rotation by slerp), and a stamp before the first or after the last sample
// of an edge takes that sample when it lies within a tolerance.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/types.h"
#include "canopy/ros2/messages.h"

namespace canopy::ros2 {

/// Every transform of a recording, by child frame (each frame has one parent).
class TfBuffer {
 public:
  /// Adds the transforms of one /tf (is_static false) or /tf_static message, stamped as their
  /// headers say. InputError (naming `where`) for a frame given a second parent, a transform to
  /// itself, or a rotation that is not a unit quaternion (|q| off 1 by more than 1e-3).
  void add(const msg::TFMessage& message, bool is_static, const std::string& where);
  /// True when a transform names `frame` as its parent or child.
  bool has_frame(const std::string& frame) const;
  /// The root of the tree holding `frame` (the frame itself when nothing is above it).
  std::string root_of(const std::string& frame) const;
  /// The edges' count and the frames, for messages.
  std::vector<std::string> frames() const;
  /// T_target_source at `stamp_ns`: source's pose in target's frame, composed along the tree.
  /// nullopt with `why` when the frames are in separate trees or an edge has no sample near
  /// enough (tolerance_ns before its first or after its last).
  std::optional<Pose> lookup(const std::string& target, const std::string& source, std::int64_t stamp_ns,
                             std::int64_t tolerance_ns, std::string* why) const;

 private:
  struct Sample {
    std::int64_t stamp_ns = 0;
    Vec3 translation = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  };
  struct Edge {
    std::string parent;
    bool is_static = false;
    mutable bool sorted = true;
    mutable std::vector<Sample> samples;  ///< One for a static edge.
  };
  std::optional<Pose> edge_at(const std::string& child, const Edge& e, std::int64_t stamp_ns, std::int64_t tolerance_ns,
                              std::string* why) const;
  std::optional<Pose> root_pose(const std::string& frame, std::int64_t stamp_ns, std::int64_t tolerance_ns,
                                std::string* why) const;
  std::map<std::string, Edge> edges_;  ///< By child frame.
};

}  // namespace canopy::ros2
