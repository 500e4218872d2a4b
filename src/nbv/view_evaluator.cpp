// One view scored by a gain over its ray set (view_evaluator.h).

#include "canopy/nbv/view_evaluator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include "canopy/common/timer.h"

namespace canopy::nbv {

const char* to_string(ViewStatus s) {
  switch (s) {
    case ViewStatus::kOk: return "ok";
    case ViewStatus::kNoRays: return "no rays in the window";
    case ViewStatus::kTargetBehind: return "target not in front of the camera";
    case ViewStatus::kInsideOccupied: return "camera inside an occupied voxel";
    case ViewStatus::kOutsideMap: return "camera outside the map";
  }
  return "?";
}

ViewEvaluator::ViewEvaluator(const VoxelIndex& index, const CameraIntrinsics& intrinsics, const RayParams& params)
    : index_(index), intrinsics_(intrinsics), params_(params) {}

bool ViewEvaluator::precheck(const Pose& T_world_camera, const Vec3& target, ViewScore* score) const {
  const mapping::SemanticOcTree* map = index_.map();
  const Vec3 eye = T_world_camera.translation();
  octomap::OcTreeKey key;
  if (!map || !eye.allFinite() || !map->key_of(eye, &key)) {
    score->status = ViewStatus::kOutsideMap;
    return false;
  }
  const VoxelInfo& at_eye = index_.info(index_.lookup(key));
  if (at_eye.known && at_eye.p_occ > 0.5f) {
    score->status = ViewStatus::kInsideOccupied;
    return false;
  }
  const Vec3 t_cam = T_world_camera.inverse() * target;
  if (!(t_cam.z() > 0.0) || !t_cam.allFinite()) {
    score->status = ViewStatus::kTargetBehind;
    return false;
  }
  return true;
}

bool ViewEvaluator::ray_segments(const Pose& T_world_camera, const Vec3& target, const RaySetEntry& rays,
                                 std::vector<Vec3>* ends, ViewStatus* status) {
  ViewScore s;
  ends->clear();
  if (!precheck(T_world_camera, target, &s)) {
    *status = s.status;
    return false;
  }
  const Vec3 t_cam = T_world_camera.inverse() * target;
  RayWindow w;
  intrinsics_.project(t_cam, &w.u_px, &w.v_px);
  w.z_m = t_cam.z();
  rays.pixels(intrinsics_, params_, w, &pixels_);
  if (pixels_.empty()) {
    *status = ViewStatus::kNoRays;
    return false;
  }
  const double depth = w.z_m + params_.depth_margin_m;
  for (const Vec2& p : pixels_) ends->push_back(T_world_camera * (intrinsics_.ray_direction(p.x(), p.y()) * depth));
  *status = ViewStatus::kOk;
  return true;
}

ViewScore ViewEvaluator::evaluate(const Pose& T, const Vec3& target, const GainFunction& gain, const RaySetEntry& rays,
                                  std::uint64_t view_seed) {
  const Stopwatch watch;
  ViewScore s;
  if (!gain.uses_rays()) {
    s.gain = gain.view_gain(0.0, view_seed);
    s.ms = watch.ms();
    return s;
  }
  ViewStatus status;
  if (!ray_segments(T, target, rays, &ends_, &status)) {
    s.status = status;
    s.ms = watch.ms();
    return s;
  }
  const Vec3 eye = T.translation();
  double longest = 0.0;
  for (const Vec3& e : ends_) longest = std::max(longest, (e - eye).norm());
  const std::size_t cap = index_.max_voxels(longest);
  if (buffer_.size() < cap) buffer_.resize(cap);
  double sum = 0.0;
  for (const Vec3& e : ends_) {
    bool outside = false;
    const std::size_t n = index_.cast(eye, e, target, buffer_.data(), buffer_.size(), &outside);
    if (outside) {
      ++s.rays_outside;
      continue;
    }
    ++s.rays;
    s.voxels += n;
    sum += gain.ray_gain(buffer_.data(), n);
  }
  s.gain = gain.view_gain(sum, view_seed);
  if (!std::isfinite(s.gain)) s.gain = 0.0;
  s.ms = watch.ms();
  return s;
}

ViewStatus ViewEvaluator::evaluate_all(const Pose& T, const Vec3& target, const std::vector<const GainFunction*>& gains,
                                       const RaySetEntry& rays, std::uint64_t view_seed, double* out,
                                       const std::function<void(const RayVoxel*, std::size_t)>& each_ray,
                                       std::vector<std::uint64_t>* bricks) {
  std::vector<double>& sums = sums_;
  sums.assign(gains.size(), 0.0);
  ViewStatus status = ViewStatus::kOk;
  if (bricks) {  // precheck() reads the camera's voxel
    octomap::OcTreeKey key;
    const Vec3 eye = T.translation();
    if (index_.map() && eye.allFinite() && index_.map()->key_of(eye, &key)) bricks->push_back(mapping::brick_key(key));
  }
  if (ray_segments(T, target, rays, &ends_, &status)) {
    const Vec3 eye = T.translation();
    double longest = 0.0;
    for (const Vec3& e : ends_) longest = std::max(longest, (e - eye).norm());
    const std::size_t cap = index_.max_voxels(longest);
    if (buffer_.size() < cap) buffer_.resize(cap);
    for (const Vec3& e : ends_) {
      bool outside = false;
      const std::size_t n = index_.cast(eye, e, target, buffer_.data(), buffer_.size(), &outside, nullptr, bricks);
      if (outside) continue;
      for (std::size_t g = 0; g < gains.size(); ++g)
        if (gains[g]->uses_rays()) sums[g] += gains[g]->ray_gain(buffer_.data(), n);
      if (each_ray) each_ray(buffer_.data(), n);
    }
  }
  for (std::size_t g = 0; g < gains.size(); ++g) {
    // A gain that casts no rays scores whatever the view's status (as evaluate() does).
    if (gains[g]->uses_rays() && status != ViewStatus::kOk) {
      out[g] = 0.0;
      continue;
    }
    out[g] = gains[g]->view_gain(sums[g], view_seed);
    if (!std::isfinite(out[g])) out[g] = 0.0;
  }
  return status;
}

ViewScore ViewEvaluator::evaluate_reference(const Pose& T, const Vec3& target, const GainFunction& gain,
                                            const RaySetEntry& rays, std::uint64_t view_seed) {
  const Stopwatch watch;
  ViewScore s;
  if (!gain.uses_rays()) {
    s.gain = gain.view_gain(0.0, view_seed);
    return s;
  }
  ViewStatus status;
  if (!ray_segments(T, target, rays, &ends_, &status)) {
    s.status = status;
    return s;
  }
  const mapping::SemanticOcTree& map = *index_.map();
  const Vec3 eye = T.translation();
  double sum = 0.0;
  for (const Vec3& e : ends_) {
    ref_voxels_.clear();
    if (!cast_reference(map, eye, e, &key_ray_, &ref_voxels_)) {
      ++s.rays_outside;
      continue;
    }
    ++s.rays;
    const std::size_t n = ref_voxels_.size();
    s.voxels += n;
    ref_infos_.resize(n);
    if (buffer_.size() < n) buffer_.resize(n);
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const mapping::SemanticState* st = ref_voxels_[i].state;
      ref_infos_[i] = make_voxel_info(map, st);
      // Run-length ids: a new id whenever the state differs from the previous voxel's.
      if (i > 0) {
        const mapping::SemanticState* prev = ref_voxels_[i - 1].state;
        const bool same = (st == nullptr && prev == nullptr) || (st && prev && *st == *prev);
        if (!same) ++id;
      }
      const Vec3 c = map.center_of(ref_voxels_[i].key);
      buffer_[i].info = &ref_infos_[i];
      buffer_[i].id = id;
      buffer_[i].dist2_m2 = float((c - target).squaredNorm());
    }
    sum += gain.ray_gain(buffer_.data(), n);
  }
  s.gain = gain.view_gain(sum, view_seed);
  if (!std::isfinite(s.gain)) s.gain = 0.0;
  s.ms = watch.ms();
  return s;
}

}  // namespace canopy::nbv
