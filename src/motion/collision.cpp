#include "canopy/motion/collision.h"

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/common/yaml_reader.h"
#include "env_tree.h"

namespace canopy::motion {

namespace {

using Geometry = fcl::CollisionGeometryd;

std::shared_ptr<Geometry> make_geometry(const robot::Shape& s, double pad) {
  std::shared_ptr<Geometry> g;
  switch (s.type) {
    case robot::ShapeType::kBox:
      g = std::make_shared<fcl::Boxd>(s.box_size.x() + 2 * pad, s.box_size.y() + 2 * pad, s.box_size.z() + 2 * pad);
      break;
    case robot::ShapeType::kSphere: g = std::make_shared<fcl::Sphered>(s.radius + pad); break;
    case robot::ShapeType::kCylinder: g = std::make_shared<fcl::Cylinderd>(s.radius + pad, s.length + 2 * pad); break;
    case robot::ShapeType::kCapsule: g = std::make_shared<fcl::Capsuled>(s.radius + pad, s.length); break;
    case robot::ShapeType::kMesh: CANOPY_CHECK(false, "mesh collision shapes are rejected by RobotModel");
  }
  g->computeLocalAABB();
  return g;
}

// World-axis bounding box of a shape (inflated by pad) at pose T.
void shape_aabb(const robot::Shape& s, const Pose& T, double pad, Vec3* lo, Vec3* hi) {
  const Mat3& R = T.linear();
  Vec3 half = Vec3::Zero();
  switch (s.type) {
    case robot::ShapeType::kBox: half = R.cwiseAbs() * (0.5 * s.box_size + Vec3::Constant(pad)); break;
    case robot::ShapeType::kSphere: half = Vec3::Constant(s.radius + pad); break;
    case robot::ShapeType::kCylinder:
      half = (0.5 * s.length + pad) * R.col(2).cwiseAbs() + Vec3::Constant(s.radius + pad);
      break;
    case robot::ShapeType::kCapsule: half = 0.5 * s.length * R.col(2).cwiseAbs() + Vec3::Constant(s.radius + pad); break;
    case robot::ShapeType::kMesh: half = Vec3::Constant(1e3); break;
  }
  *lo = T.translation() - half;
  *hi = T.translation() + half;
}

bool collide(const Geometry& a, const Pose& Ta, const Geometry& b, const Pose& Tb) {
  // One contact, no contact details: the cheapest query FCL offers.
  static const fcl::CollisionRequestd request(1, false);
  fcl::CollisionResultd result;
  return fcl::collide(&a, Ta, &b, Tb, request, result) > 0;
}

}  // namespace

// ----------------------------------------------------------------------------------------
// A coarse occupancy grid beside the octree: FCL's octree traversal costs several
// microseconds even far from any voxel, so shapes whose bounding box touches no marked
// coarse cell skip it (an exact, conservative test). Cells are marked when a voxel is added
// and never unmarked (a stale mark only costs an octree query); the grid grows to cover new
// voxels.
struct CoarseGrid {
  Vec3 origin = Vec3::Zero();
  double cell = 0.06;
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<std::uint8_t> occupied;

  bool any(const Vec3& lo, const Vec3& hi) const {
    if (occupied.empty()) return false;
    Eigen::Vector3i a, b;
    for (int i = 0; i < 3; ++i) {
      a[i] = std::max(0, static_cast<int>(std::floor((lo[i] - origin[i]) / cell)));
      b[i] = std::min(dims[i] - 1, static_cast<int>(std::floor((hi[i] - origin[i]) / cell)));
      if (a[i] > b[i]) return false;
    }
    for (int z = a.z(); z <= b.z(); ++z)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int x = a.x(); x <= b.x(); ++x)
          if (occupied[index(x, y, z)]) return true;
    return false;
  }
  std::size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * dims.y() + y) * dims.x() + x; }
  bool covers(const Vec3& lo, const Vec3& hi) const {
    if (occupied.empty()) return false;
    for (int i = 0; i < 3; ++i)
      if (lo[i] < origin[i] || hi[i] >= origin[i] + dims[i] * cell) return false;
    return true;
  }
  // Re-lays the grid over [lo, hi] (which must contain the old extent), keeping the marks.
  void grow(const Vec3& lo_in, const Vec3& hi_in) {
    const double margin = 8 * cell;  // room for the next voxels without another copy
    const Vec3 lo = ((lo_in - Vec3::Constant(margin)) / cell).array().floor() * cell;
    const Vec3 hi = hi_in + Vec3::Constant(margin);
    CoarseGrid g;
    g.cell = cell;
    g.origin = lo;
    for (int i = 0; i < 3; ++i) g.dims[i] = std::max(1, static_cast<int>(std::ceil((hi[i] - lo[i]) / cell)));
    g.occupied.assign(static_cast<size_t>(g.dims.x()) * g.dims.y() * g.dims.z(), 0);
    for (int z = 0; z < dims.z(); ++z)
      for (int y = 0; y < dims.y(); ++y)
        for (int x = 0; x < dims.x(); ++x) {
          if (!occupied[index(x, y, z)]) continue;
          const Vec3 c = origin + (Vec3(x, y, z) + Vec3::Constant(0.5)) * cell;
          const Eigen::Vector3i k = ((c - g.origin) / cell).array().floor().cast<int>();
          g.occupied[g.index(k.x(), k.y(), k.z())] = 1;
        }
    *this = std::move(g);
  }
  void mark(const Vec3& lo, const Vec3& hi) {
    if (!covers(lo, hi)) {
      Vec3 l = lo, h = hi;
      if (!occupied.empty()) {
        // Grow geometrically along each axis that must grow (at least the old extent again),
        // so that voxels added along a long row cost amortised O(1) copies, not one copy of the
        // whole grid every few cells.
        const Vec3 old_lo = origin, old_hi = origin + dims.cast<double>() * cell;
        const Vec3 extent = old_hi - old_lo;
        for (int i = 0; i < 3; ++i) {
          if (l[i] < old_lo[i]) l[i] = std::min(l[i], old_lo[i] - extent[i]);
          if (h[i] >= old_hi[i]) h[i] = std::max(h[i], old_hi[i] + extent[i]);
        }
        l = l.cwiseMin(old_lo);
        h = h.cwiseMax(old_hi);
      }
      grow(l, h);
    }
    const Eigen::Vector3i a = ((lo - origin) / cell).array().floor().cast<int>();
    const Eigen::Vector3i b = ((hi - origin) / cell).array().floor().cast<int>();
    for (int z = std::max(0, a.z()); z <= std::min(dims.z() - 1, b.z()); ++z)
      for (int y = std::max(0, a.y()); y <= std::min(dims.y() - 1, b.y()); ++y)
        for (int x = std::max(0, a.x()); x <= std::min(dims.x() - 1, b.x()); ++x) occupied[index(x, y, z)] = 1;
  }
};

using env_tree::EnvTree;
using env_tree::kWindowDepth;
using env_tree::kWindowShift;
using env_tree::window_code;

struct CollisionEnvironment::Impl {
  std::shared_ptr<EnvTree> octomap;
  std::shared_ptr<fcl::OcTreed> octree;
  CoarseGrid coarse;
  // keep_x(): the tree holds the subtrees of window node x [window_lo, window_hi] (and leaves
  // above them); the others are in `dropped` (by window_code), written out compactly.
  bool windowed = false;
  unsigned window_lo = 0, window_hi = 0;
  std::unordered_map<std::uint64_t, std::vector<std::uint8_t>> dropped;
  std::size_t dropped_bytes = 0;

  // Key x range [first, last] held whole (every voxel's subtree in the tree).
  bool holds_keys_x(unsigned first, unsigned last) const {
    return !windowed || ((first >> kWindowShift) >= window_lo && (last >> kWindowShift) <= window_hi);
  }
  // World x range [lo, hi] (a query's box) held whole, a voxel of margin included.
  bool holds_x(double lo, double hi) const {
    if (!windowed) return true;
    const double res = octomap->getResolution();
    const double first = std::floor(lo / res) - 1.0 + 32768.0, last = std::floor(hi / res) + 1.0 + 32768.0;
    if (!(first >= 0.0 && last <= 65535.0)) return false;
    return holds_keys_x(unsigned(first), unsigned(last));
  }
  // True when the subtree holding `key` was moved out (the tree does not answer there).
  bool dropped_at(const octomap::OcTreeKey& key) const {
    if (!windowed || dropped.empty()) return false;
    const unsigned ix = unsigned(key[0]) >> kWindowShift;
    if (ix >= window_lo && ix <= window_hi) return false;
    return dropped.count(window_code(ix, unsigned(key[1]) >> kWindowShift, unsigned(key[2]) >> kWindowShift)) > 0;
  }
  // Puts back the dropped subtree holding `key`, if any (before the tree is changed or read there).
  void restore_at(const octomap::OcTreeKey& key) {
    if (!windowed || dropped.empty()) return;
    const unsigned ix = unsigned(key[0]) >> kWindowShift;
    if (ix >= window_lo && ix <= window_hi) return;
    const unsigned iy = unsigned(key[1]) >> kWindowShift, iz = unsigned(key[2]) >> kWindowShift;
    const auto it = dropped.find(window_code(ix, iy, iz));
    if (it == dropped.end()) return;
    octomap->restore(kWindowDepth, ix, iy, iz, it->second);
    dropped_bytes -= it->second.size();
    dropped.erase(it);
  }
};

CollisionEnvironment::~CollisionEnvironment() = default;

std::size_t CollisionEnvironment::memory_bytes() const {
  return impl_->octomap->memoryUsage() + impl_->coarse.occupied.capacity() + impl_->dropped_bytes +
         impl_->dropped.size() * 64;
}

void CollisionEnvironment::keep_x(double x_lo_m, double x_hi_m) {
  CANOPY_CHECK(std::isfinite(x_lo_m) && std::isfinite(x_hi_m) && x_lo_m <= x_hi_m,
               "CollisionEnvironment::keep_x: [" << x_lo_m << ", " << x_hi_m << "] is not a stretch");
  Impl& m = *impl_;
  auto window_x = [&](double x) {
    const double k = std::clamp(std::floor(x / resolution_m_) + 32768.0, 0.0, 65535.0);
    return unsigned(k) >> kWindowShift;
  };
  const unsigned lo = window_x(x_lo_m), hi = window_x(x_hi_m);
  if (m.windowed && lo == m.window_lo && hi == m.window_hi) return;
  m.windowed = true;
  m.window_lo = lo;
  m.window_hi = hi;
  // Back first: the subtrees now inside.
  std::vector<std::uint64_t> back;
  for (const auto& [code, bytes] : m.dropped) {
    const unsigned ix = unsigned(code & 0x3ffu);
    if (ix >= lo && ix <= hi) back.push_back(code);
  }
  std::sort(back.begin(), back.end());  // one order whatever the hash table's
  for (const std::uint64_t code : back) {
    const auto it = m.dropped.find(code);
    m.octomap->restore(kWindowDepth, unsigned(code & 0x3ffu), unsigned((code >> 10) & 0x3ffu),
                       unsigned((code >> 20) & 0x3ffu), it->second);
    m.dropped_bytes -= it->second.size();
    m.dropped.erase(it);
  }
  m.octomap->drop_outside(kWindowDepth, lo, hi, [&](unsigned ix, unsigned iy, unsigned iz, std::vector<std::uint8_t> bytes) {
    m.dropped_bytes += bytes.size();
    bytes.shrink_to_fit();
    m.dropped.emplace(window_code(ix, iy, iz), std::move(bytes));
  });
  m.octree->computeLocalAABB();
}

void CollisionEnvironment::keep_all() {
  Impl& m = *impl_;
  if (!m.windowed) return;
  keep_x(-1e300, 1e300);  // every subtree back
  m.windowed = false;
}

bool CollisionEnvironment::windowed() const { return impl_->windowed; }
void CollisionEnvironment::write(std::ostream& out) const { impl_->octomap->write(out); }
std::size_t CollisionEnvironment::dropped_subtrees() const { return impl_->dropped.size(); }

std::shared_ptr<CollisionEnvironment> CollisionEnvironment::empty(double resolution_m) {
  if (!(std::isfinite(resolution_m) && resolution_m > 0.0))
    throw InputError("collision environment: resolution " + std::to_string(resolution_m) + " m must be > 0");
  std::shared_ptr<CollisionEnvironment> env(new CollisionEnvironment());
  env->impl_ = std::make_unique<Impl>();
  env->impl_->octomap = std::make_shared<EnvTree>(resolution_m);
  env->impl_->coarse.cell = std::max(4.0 * resolution_m, 0.02);
  env->impl_->octree = std::make_shared<fcl::OcTreed>(env->impl_->octomap);
  env->impl_->octree->computeLocalAABB();
  env->resolution_m_ = resolution_m;
  return env;
}

std::shared_ptr<const CollisionEnvironment> CollisionEnvironment::from_voxels(const std::vector<Vec3>& centres,
                                                                              double resolution_m) {
  auto env = empty(resolution_m);
  env->update(centres, {});
  return env;
}

void CollisionEnvironment::update(const std::vector<Vec3>& occupied, const std::vector<Vec3>& freed) {
  octomap::OcTree& tree = *impl_->octomap;
  if (impl_->windowed) {  // a change where a subtree was moved out: back first (keep_x)
    for (const std::vector<Vec3>* points : {&freed, &occupied})
      for (const Vec3& c : *points) {
        octomap::OcTreeKey key;
        if (c.allFinite() && tree.coordToKeyChecked(c.x(), c.y(), c.z(), key)) impl_->restore_at(key);
      }
  }
  const float occ = tree.getClampingThresMaxLog(), free = tree.getClampingThresMinLog();
  const double h = 0.5 * resolution_m_;
  bool changed = false;
  // Leaves are set without lazy evaluation, so the inner nodes FCL descends through (their
  // maximum occupancy) stay right after every change.
  for (const Vec3& c : freed) {
    octomap::OcTreeKey key;
    if (!c.allFinite() || !tree.coordToKeyChecked(c.x(), c.y(), c.z(), key)) continue;
    const octomap::OcTreeNode* n = tree.search(key);
    if (!n || !tree.isNodeOccupied(n)) continue;
    tree.setNodeValue(key, free, /*lazy_eval=*/false);
    --voxel_count_;
    changed = true;
  }
  for (const Vec3& c : occupied) {
    octomap::OcTreeKey key;
    if (!c.allFinite() || !tree.coordToKeyChecked(c.x(), c.y(), c.z(), key)) continue;
    const octomap::OcTreeNode* n = tree.search(key);
    if (n && tree.isNodeOccupied(n)) continue;
    tree.setNodeValue(key, occ, /*lazy_eval=*/false);
    const Vec3 centre(tree.keyToCoord(key[0]), tree.keyToCoord(key[1]), tree.keyToCoord(key[2]));
    impl_->coarse.mark(centre - Vec3::Constant(h), centre + Vec3::Constant(h));
    ++voxel_count_;
    changed = true;
  }
  if (changed) impl_->octree->computeLocalAABB();
}

double point_shape_distance(const robot::Shape& s, const Pose& T_world_shape, const Vec3& p_world) {
  const Vec3 p = T_world_shape.inverse(Eigen::Isometry) * p_world;
  switch (s.type) {
    case robot::ShapeType::kBox: return (p.cwiseAbs() - 0.5 * s.box_size).cwiseMax(0.0).norm();
    case robot::ShapeType::kSphere: return std::max(0.0, p.norm() - s.radius);
    case robot::ShapeType::kCapsule: {
      const double z = std::clamp(p.z(), -0.5 * s.length, 0.5 * s.length);
      return std::max(0.0, (p - Vec3(0, 0, z)).norm() - s.radius);
    }
    case robot::ShapeType::kCylinder: {
      const double radial = std::max(0.0, std::hypot(p.x(), p.y()) - s.radius);
      const double axial = std::max(0.0, std::abs(p.z()) - 0.5 * s.length);
      return std::hypot(radial, axial);
    }
    case robot::ShapeType::kMesh: break;
  }
  return 1e9;
}

std::size_t CollisionEnvironment::clear_robot_volume(const RobotModel& model, const BasePose& base, const ArmConfig& q,
                                                     double padding_m) {
  octomap::OcTree& tree = *impl_->octomap;
  std::vector<Pose> poses;
  model.body_poses(base, q, &poses);
  const double reach = padding_m + std::sqrt(3.0) * 0.5 * resolution_m_;  // a voxel cube touching the shape
  std::vector<octomap::OcTreeKey> hits;
  for (std::size_t b = 0; b < model.bodies().size(); ++b) {
    const robot::Shape& shape = model.bodies()[b].shape;
    Vec3 lo, hi;
    shape_aabb(shape, poses[b], reach, &lo, &hi);
    if (!impl_->coarse.any(lo, hi)) continue;  // no voxel near this shape
    CANOPY_CHECK(impl_->holds_x(lo.x(), hi.x()), "collision environment: the robot's volume at x = "
                                                     << base.x_m << " reaches beyond the stretch held (keep_x)");
    for (auto it = tree.begin_leafs_bbx(octomap::point3d(lo.x(), lo.y(), lo.z()), octomap::point3d(hi.x(), hi.y(), hi.z())),
              end = tree.end_leafs_bbx();
         it != end; ++it) {
      if (!tree.isNodeOccupied(*it)) continue;
      // A pruned block of occupied voxels is tested voxel by voxel.
      const int n = static_cast<int>(std::lround(it.getSize() / resolution_m_));
      const Vec3 corner = Vec3(it.getX(), it.getY(), it.getZ()) - Vec3::Constant(0.5 * it.getSize() - 0.5 * resolution_m_);
      for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x) {
            const Vec3 c = corner + resolution_m_ * Vec3(x, y, z);
            octomap::OcTreeKey key;
            if (point_shape_distance(shape, poses[b], c) <= reach && tree.coordToKeyChecked(c.x(), c.y(), c.z(), key))
              hits.push_back(key);
          }
    }
  }
  std::vector<Vec3> freed;
  for (const octomap::OcTreeKey& k : hits) freed.push_back(Vec3(tree.keyToCoord(k[0]), tree.keyToCoord(k[1]), tree.keyToCoord(k[2])));
  const std::size_t before = voxel_count_;
  update({}, freed);
  return before - voxel_count_;
}

void CollisionEnvironment::follow_scan(const mapping::SemanticOcTree& map,
                                       const std::vector<mapping::VoxelUpdate>& updates,
                                       const std::vector<std::uint8_t>& occupancy) {
  CANOPY_CHECK(occupancy.size() == updates.size(), "one occupancy byte per update");
  using T = mapping::SemanticOcTree;
  if (impl_->windowed)  // occupied() below reads where a subtree may have been moved out: back first
    for (const mapping::VoxelUpdate& u : updates) impl_->restore_at(mapping::morton_key(u.code));
  std::vector<Vec3> occupied_now, freed;
  for (std::size_t i = 0; i < updates.size(); ++i) {
    const bool after = occupancy[i] & T::kOccupiedAfter, hit = updates[i].label != mapping::VoxelUpdate::kFree;
    if (!after && !hit && !(occupancy[i] & T::kOccupiedBefore)) continue;
    const Vec3 c = map.center_of(mapping::morton_key(updates[i].code));
    if (after) occupied_now.push_back(c);
    else if (hit || occupied(c)) freed.push_back(c);
  }
  update(occupied_now, freed);
}

bool CollisionEnvironment::occupied(const Vec3& p) const {
  const octomap::OcTree& tree = *impl_->octomap;
  octomap::OcTreeKey key;
  if (!p.allFinite() || !tree.coordToKeyChecked(p.x(), p.y(), p.z(), key)) return false;
  CANOPY_CHECK(!impl_->dropped_at(key), "collision environment: x = " << p.x() << " is in a subtree moved out (keep_x)");
  const octomap::OcTreeNode* n = tree.search(key);
  return n && tree.isNodeOccupied(n);
}

// A shape (its padded geometry, at `pose`) against the map: the coarse grid first, then FCL.
static bool map_hit(const CollisionEnvironment::Impl& env, const robot::Shape& shape, const Geometry& padded, const Pose& pose,
             double pad) {
  Vec3 lo, hi;
  shape_aabb(shape, pose, pad, &lo, &hi);
  if (!env.coarse.any(lo, hi)) return false;
  // What the tree does not hold is never asked (keep_x): a shape reaching there is an error.
  CANOPY_CHECK(env.holds_x(lo.x(), hi.x()), "collision environment: a robot shape at x = " << pose.translation().x()
                                                << " reaches beyond the stretch held (keep_x)");
  return collide(padded, pose, *env.octree, Pose::Identity());
}

// ----------------------------------------------------------------------------------------
struct CollisionChecker::Shapes {
  std::vector<std::shared_ptr<Geometry>> padded;  // Against the map and the ground.
  std::vector<std::shared_ptr<Geometry>> self;    // Against each other.
  std::shared_ptr<Geometry> ground;
};

CollisionChecker::~CollisionChecker() = default;
CollisionChecker::CollisionChecker(CollisionChecker&&) noexcept = default;

CollisionChecker::CollisionChecker(const RobotModel& model, const CollisionParams& params,
                                   std::shared_ptr<const CollisionEnvironment> environment)
    : model_(&model), params_(params), environment_(std::move(environment)), shapes_(std::make_unique<Shapes>()) {
  params_.validate();
  const auto& bodies = model.bodies();
  for (const CollisionBody& b : bodies) {
    shapes_->padded.push_back(make_geometry(b.shape, params_.environment_padding_m));
    shapes_->self.push_back(make_geometry(b.shape, params_.self_padding_m));
  }
  shapes_->ground = std::make_shared<fcl::Halfspaced>(Vec3::UnitZ(), params_.ground_height_m);
  shapes_->ground->computeLocalAABB();
  for (size_t i = 0; i < bodies.size(); ++i) {
    for (size_t j = i + 1; j < bodies.size(); ++j) {
      if (!model.links_adjacent(bodies[i].link, bodies[j].link))
        self_pairs_.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
  }
}

bool CollisionChecker::in_collision(const BasePose& base, const ArmConfig& q, BodySet set) const {
  return check(base, q, set, nullptr);
}

CollisionReport CollisionChecker::report(const BasePose& base, const ArmConfig& q) const {
  CollisionReport r;
  r.in_collision = check(base, q, BodySet::kAll, &r);
  return r;
}

bool CollisionChecker::base_in_collision(const BasePose& base) const {
  if (!std::isfinite(base.x_m) || !std::isfinite(base.y_m) || !std::isfinite(base.yaw_rad)) return true;
  std::vector<Pose> poses;
  model_->body_poses(base, model_->config().home, &poses);
  const auto& bodies = model_->bodies();
  for (size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b].on_arm) continue;
    if (params_.check_ground && collide(*shapes_->padded[b], poses[b], *shapes_->ground, Pose::Identity()))
      return true;
    if (environment_) {
      Vec3 lo, hi;
      shape_aabb(bodies[b].shape, poses[b], params_.environment_padding_m, &lo, &hi);
      CANOPY_CHECK(environment_->impl().holds_x(lo.x(), hi.x()),
                   "collision environment: the base at x = " << base.x_m << " reaches beyond the stretch held (keep_x)");
      if (collide(*shapes_->padded[b], poses[b], *environment_->impl().octree, Pose::Identity())) return true;
    }
  }
  return false;
}

bool CollisionChecker::check(const BasePose& base, const ArmConfig& q, BodySet set, CollisionReport* report) const {
  bool finite = std::isfinite(base.x_m) && std::isfinite(base.y_m) && std::isfinite(base.yaw_rad);
  for (double v : q) finite = finite && std::isfinite(v);
  if (!finite) {
    if (report) report->pairs.push_back("non-finite state");
    return true;
  }
  thread_local std::vector<Pose> poses;
  model_->body_poses(base, q, &poses);
  const auto& bodies = model_->bodies();
  bool hit = false;
  auto found = [&](const std::string& what) {
    hit = true;
    if (report) report->pairs.push_back(what);
    return report == nullptr;  // Stop at the first hit unless reporting.
  };

  // A yes/no answer is the same in any order of the tests; the map is hit most often by the
  // shapes nearest the camera (the arm reaching into the foliage), so those are asked first and
  // most states in collision are decided by one octree query (issue 47). A report keeps the
  // order below.
  const double pad = params_.environment_padding_m;
  if (!report) {
    for (size_t k = bodies.size(); k-- > 0;) {
      if (set == BodySet::kArmOnly && !bodies[k].on_arm) continue;
      if (environment_ && map_hit(environment_->impl(), bodies[k].shape, *shapes_->padded[k], poses[k], pad)) return true;
    }
  }
  // Self-collision: cheap bounding-sphere rejection removes most pairs.
  for (const auto& [i, j] : self_pairs_) {
    const auto ui = static_cast<size_t>(i), uj = static_cast<size_t>(j);
    const double reach = bodies[ui].bounding_radius_m + bodies[uj].bounding_radius_m + 2 * params_.self_padding_m;
    if ((poses[ui].translation() - poses[uj].translation()).squaredNorm() > reach * reach) continue;
    if (collide(*shapes_->self[ui], poses[ui], *shapes_->self[uj], poses[uj]) &&
        found(bodies[ui].shape.name + " | " + bodies[uj].shape.name))
      return true;
  }
  for (size_t b = 0; b < bodies.size(); ++b) {
    if (set == BodySet::kArmOnly && !bodies[b].on_arm) continue;
    const double lowest = poses[b].translation().z() - bodies[b].bounding_radius_m - params_.environment_padding_m;
    if (params_.check_ground && lowest <= params_.ground_height_m &&
        collide(*shapes_->padded[b], poses[b], *shapes_->ground, Pose::Identity()) &&
        found(bodies[b].shape.name + " | ground"))
      return true;
    if (environment_ && report && map_hit(environment_->impl(), bodies[b].shape, *shapes_->padded[b], poses[b], pad) &&
        found(bodies[b].shape.name + " | map"))
      return true;
  }
  return hit;
}

std::optional<BasePose> held_arm_sweep_hit(const CollisionChecker& checker, const BasePose& from, const BasePose& to,
                                           const ArmConfig& q, double step_m, double x_lo_m, double x_hi_m) {
  if (!(step_m > 0.0)) throw InputError("held_arm_sweep_hit: step must be > 0, got " + std::to_string(step_m));
  const double distance_m = std::hypot(to.x_m - from.x_m, to.y_m - from.y_m);
  const int n = std::max(1, static_cast<int>(std::ceil(distance_m / step_m)));
  for (int i = 1; i <= n; ++i) {
    const double f = static_cast<double>(i) / n;
    BasePose b = from;
    b.x_m = from.x_m + f * (to.x_m - from.x_m);
    b.y_m = from.y_m + f * (to.y_m - from.y_m);
    if (b.x_m < x_lo_m || b.x_m > x_hi_m) continue;
    if (checker.in_collision(b, q, BodySet::kArmOnly)) return b;
  }
  return std::nullopt;
}

}  // namespace canopy::motion
