#pragma once
// Candidate views around a cluster centroid (paper Methods (iii)): N_theta x N_phi camera
// positions on a sphere of radius r, each looking at the centroid with zero roll.

#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/types.h"
#include "canopy/nbv/nbv_params.h"

namespace canopy::nbv {

/// One candidate view of a cluster.
struct Candidate {
  Pose T_world_camera = Pose::Identity();
  Vec3 target = Vec3::Zero();   ///< The centroid it looks at.
  int cluster = -1;             ///< Index of the cluster.
  double polar_deg = 0.0;       ///< Angle from world +z at the centroid.
  double azimuth_deg = 0.0;     ///< Angle about world z from +x.
  // What a reachability check (the arm's workspace filter) found, when one ran.
  double shift_m = 0.0;         ///< Move along the viewing direction (+ towards the target).
  bool has_q = false;           ///< q holds an IK solution of T_world_camera.
  ArmConfig q{};
};

/// Candidates on the sphere around `centroid`: polar angles evenly in [min, max] (one angle:
/// their mean), azimuths k * 360 / N_phi for k < N_phi (no duplicate at 360). Candidates
/// below params.min_height_m are dropped. Polar-major order.
std::vector<Candidate> sample_candidates(const Vec3& centroid, int cluster, const CandidateParams& params);

}  // namespace canopy::nbv
