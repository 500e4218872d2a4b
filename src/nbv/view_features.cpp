// The features of a candidate view for a learned scorer (view_features.h).

#include "canopy/nbv/view_features.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/nbv/view_evaluator.h"

namespace canopy::nbv {

namespace {

// The ray sets whose gains are features: the cheap ones (ours' window and the sparse grid; the
// dense grid casts 20x more rays than a planning budget allows).
const char* const kFeatureRaySets[] = {"ours", "sparse"};

// Every gain of the registry that reads the map (rs, random, is not a feature), each
// proximity test of the gains that have one apart, as the candidate audit names them.
struct FeatureGain {
  std::string name;
  const GainEntry* entry;
  Proximity proximity;
  bool sets_proximity;
};

std::vector<FeatureGain> feature_gains() {
  std::vector<FeatureGain> out;
  for (const GainEntry& g : gain_registry()) {
    if (g.name == "rs") continue;
    if (!g.uses_proximity) {
      out.push_back({g.name, &g, Proximity::kPerVoxel, false});
      continue;
    }
    for (const auto& p : kProximityNames) out.push_back({g.name + "_" + p.name, &g, p.value, true});
  }
  return out;
}

// The features after the gains, in order.
const char* const kOtherFeatures[] = {
    "ours_rays_blocked",      // rays of ours' window whose first occupied voxel is not the target class
    "ours_rays_on_target",    // ... whose first occupied voxel is the target class
    "ours_rays_unknown",      // unknown voxels per ray of ours' window (mean)
    "shape_seen",             // unseen predicted fruit surface points seen (the shape planner's score)
    "shape_seen_fruit_prob",  // the same, points in another class's voxel counted by their fruit probability
    "shape_seen_target",      // shape_seen of the target fruit alone
    "shape_in_view",          // unseen predicted points in the image, depth range and facing the camera
    "shape_blocked",          // the share of those whose sight line meets an occupied voxel
    "fit_ok",                 // the target fruit's shape fit succeeded (1) or is the prior (0)
    "fit_rms_mm",             // its voxels' RMS distance to the fitted surface
    "fruit_voxels",           // its confirmed fruit voxels
    "fruit_seen",             // the share of its predicted surface already covered
    "fruit_label_consistency",// its voxels' mean fruit probability among their occupied classes
    "fruit_unseen_points",    // its unseen predicted surface points
    "fruits",                 // fitted fruits of the stop region
    "unseen_points",          // their unseen predicted surface points
    "target_distance_m",      // camera to target
    "target_axis_deg",        // optical axis to the line of sight to the target
    "target_elevation_m",     // camera height above the target
    "unseen_side_cos",        // cos(angle) of the view direction and the fruit's unseen side
    "move_m",                 // camera translation from the camera now
    "move_deg",               // camera rotation from the camera now
};

// The target fruit's evidence (its voxels' class log-odds, what lies inside and around its fit),
// after the others.
const char* const kEvidenceFeatures[] = {
    "fruit_logodds_mean",     // its voxels' mean fruit log-odds (how often hit as fruit; saturates)
    "fruit_logodds_min",      // its weakest voxel's fruit log-odds
    "fruit_other_logodds",    // its voxels' mean log-odds of their strongest other class (hit as leaf...)
    "fruit_inside_unknown",   // the share of voxels inside its fitted ellipsoid never observed
    "fruit_inside_free",      // ... observed free (the fit is refuted there)
    "fruit_inside_other",     // ... occupied by another class (a leaf in front of or inside it)
    "fruit_around_unknown",   // the share of unknown voxels in the shell out to 1.5 times its fit
    "fruit_size_ratio",       // its fit's volume over the prior's, cube root
    "fruit_elongation",       // its fit's longest semi-axis over its shortest
    "fruit_neighbours",       // other fitted fruits whose centre lies within 0.15 m of its centre
    "fruit_unseen_share",     // its unseen predicted points over all fruits' of the stop region
};

using Evidence = std::array<float, std::size(kEvidenceFeatures)>;
// Fitted fruits whose centres lie this close count as neighbours [m].
constexpr double kNeighbourM = 0.15;
// The shell around a fruit's fit reaches this multiple of its semi-axes.
constexpr double kAroundScale = 1.5;
// A fit whose shell reaches farther than this from its centre is not walked (evidence missing) [m].
constexpr double kMaxReachM = 0.3;

// Surface area of an ellipsoid (Knud Thomsen's approximation, within 1.1 %).
double ellipsoid_area(const Vec3& s) {
  const double p = 1.6075;
  const double ap = std::pow(s.x(), p), bp = std::pow(s.y(), p), cp = std::pow(s.z(), p);
  return 4.0 * M_PI * std::pow((ap * bp + ap * cp + bp * cp) / 3.0, 1.0 / p);
}

}  // namespace

bool sphere_out_of_view(const CameraIntrinsics& K, const Pose& T_world_camera, const Vec3& centre_world,
                        double radius_m) {
  // The loop computes each point's camera coordinates (T^-1 p) and projection apart; these
  // differ from the sphere's by at most radius_m plus rounding (~1e-15 m), so a margin of
  // 1e-6 m (in the planes' units: times their normal's length) decides only clear cases.
  constexpr double kMargin = 1e-6;
  const Vec3 c = T_world_camera.inverse(Eigen::Isometry) * centre_world;
  const double r = radius_m + kMargin;
  if (c.z() + r < K.min_range_m || c.z() - r > K.max_range_m) return true;
  // A point in the depth range has z > 0 (or fails project()); then u < 0 iff fx x + cx z < 0,
  // u >= width iff fx x + (cx - width) z >= 0, and alike for v: planes through the eye.
  const auto beyond = [&](double a, double b, double coord) {  // plane a * coord + b * z, its sign
    const double n = std::hypot(a, b);
    const double s = a * coord + b * c.z();
    return s + r * n < 0.0 ? -1 : s - r * n > 0.0 ? 1 : 0;
  };
  if (K.min_range_m <= 0.0) return false;  // z may be 0: leave such views to the loop
  return beyond(K.fx_px, K.cx_px, c.x()) < 0 || beyond(K.fx_px, K.cx_px - K.width_px, c.x()) > 0 ||
         beyond(K.fy_px, K.cy_px, c.y()) < 0 || beyond(K.fy_px, K.cy_px - K.height_px, c.y()) > 0;
}

const std::vector<std::string>& view_feature_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const char* rays : kFeatureRaySets)
      for (const FeatureGain& g : feature_gains()) n.push_back(g.name + "@" + rays);
    for (const char* f : kOtherFeatures) n.push_back(f);
    for (const char* f : kEvidenceFeatures) n.push_back(f);
    return n;
  }();
  return names;
}

struct ViewFeatures::Fruit {
  double label_consistency = 0.0;
  double seen = 0.0;
  int unseen_points = 0;
  Vec3 unseen_side = Vec3::Zero();  // from the seen voxels' centroid to the fitted centre (unit; 0 when unknown)
  Evidence evidence{};  // kEvidenceFeatures, in order
};

namespace {

// A fruit's voxels' class log-odds, summed voxel by voxel.
struct LogoddsSums {
  double fruit = 0.0, other = 0.0;  // the fruit class's; the strongest other class's (or "others")
  float lowest = std::numeric_limits<float>::quiet_NaN();  // the lowest fruit log-odds
  int voxels = 0;
  void add(const mapping::SemanticState& s, int target) {
    const float l = s.class_logodds(target);
    float o = s.others;
    for (int i = 0; i < s.count; ++i)
      if (s.class_id[std::size_t(i)] != target) o = std::max(o, s.logodds[std::size_t(i)]);
    fruit += l;
    other += o;
    lowest = voxels == 0 ? l : std::min(lowest, l);
    ++voxels;
  }
};

// The evidence features of fruit `f` among `fruits` (kEvidenceFeatures, in order): its voxels'
// class log-odds (`logodds`), the voxels inside and around its fit as `index` has them.
Evidence fruit_evidence(const mapping::SemanticOcTree& map, const VoxelIndex& index, const std::vector<FittedFruit>& fruits,
                        std::size_t f, const LogoddsSums& logodds, int unseen_points, std::size_t all_unseen_points,
                        const mapping::ShapeFitParams& fit) {
  const FittedFruit& fr = fruits[f];
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // The voxels inside the fit and in the shell around it.
  const mapping::FruitShape& shape = fr.shape;
  int inside = 0, unknown = 0, free = 0, other = 0, around = 0, around_unknown = 0;
  octomap::OcTreeKey k0, k1;
  const Vec3 reach = shape.semi_axes * kAroundScale;
  if (shape.semi_axes.minCoeff() > 0.0 && reach.maxCoeff() <= kMaxReachM && map.key_of(shape.centre - reach, &k0) &&
      map.key_of(shape.centre + reach, &k1)) {
    for (int x = k0[0]; x <= int(k1[0]); ++x)
      for (int y = k0[1]; y <= int(k1[1]); ++y)
        for (int z = k0[2]; z <= int(k1[2]); ++z) {
          const octomap::OcTreeKey k(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                                     static_cast<octomap::key_type>(z));
          const octomap::point3d c = map.keyToCoord(k);
          const Vec3 p(c.x(), c.y(), c.z());
          if (!shape.inside(p, kAroundScale)) continue;
          const VoxelInfo& info = index.info(index.lookup(k));
          if (!shape.inside(p)) {
            ++around;
            around_unknown += !info.known;
            continue;
          }
          ++inside;
          if (!info.known) ++unknown;
          else if (!(info.p_occ > 0.5f)) ++free;
          else if (!info.is_target) ++other;
        }
  }
  const auto share = [&](int a, int b) { return b > 0 ? float(double(a) / b) : nan; };
  const Vec3& a = shape.semi_axes;
  const double prior = fit.prior_horizontal_m * fit.prior_horizontal_m * fit.prior_vertical_m;
  int neighbours = 0;
  for (std::size_t g = 0; g < fruits.size(); ++g)
    neighbours += g != f && (fruits[g].shape.centre - shape.centre).norm() < kNeighbourM;
  const int n = logodds.voxels;
  return {n > 0 ? float(logodds.fruit / n) : nan,
          logodds.lowest,
          n > 0 ? float(logodds.other / n) : nan,
          share(unknown, inside),
          share(free, inside),
          share(other, inside),
          share(around_unknown, around),
          a.minCoeff() > 0.0 ? float(std::cbrt(a.prod() / prior)) : nan,
          a.minCoeff() > 0.0 ? float(a.maxCoeff() / a.minCoeff()) : nan,
          float(neighbours),
          all_unseen_points > 0 ? float(double(unseen_points) / double(all_unseen_points)) : 0.f};
}

}  // namespace

ViewFeatures::ViewFeatures(const CameraIntrinsics& intrinsics, const NbvParams& nbv, const ViewFeatureParams& params)
    : intrinsics_(intrinsics), nbv_(nbv), params_(params) {
  for (const FeatureGain& g : feature_gains()) {
    GainParams gp = nbv.gain;
    if (g.sets_proximity) gp.proximity = g.proximity;
    gains_.push_back(g.entry->make(gp));
    gain_ptrs_.push_back(gains_.back().get());
  }
  for (const char* r : kFeatureRaySets) ray_sets_.push_back(&ray_set(r, "view features"));
}

ViewFeatures::~ViewFeatures() = default;

void ViewFeatures::begin_round(const mapping::SemanticOcTree& map, const VoxelIndex& index,
                               const Eigen::AlignedBox3d& region, const Pose& T_world_camera) {
  index_ = &index;
  T_now_ = T_world_camera;
  eval_ = std::make_unique<ViewEvaluator>(index, intrinsics_, nbv_.rays);
  std::vector<Vec3> confirmed;
  fruits_ = fit_fruits(map, params_.clustering(nbv_.cluster), params_.fit, &region, params_.margin_m, &confirmed, &cache_);
  points_ = unseen_surface(fruits_, confirmed, params_.spacing_m, params_.covered_m);
  const int target = map.classes().target_index();
  const int fruit_cat = target + 1;  // prob[] holds free first
  // Predicted points: refuted in a voxel known free; in another class's surface refuted by
  // shape's rule (weights_) or counted by the voxel's fruit probability (fruit_weights_).
  std::vector<PredictedPoint> kept;
  weights_.clear();
  fruit_weights_.clear();
  for (const PredictedPoint& p : points_) {
    octomap::OcTreeKey k;
    if (!map.key_of(p.position, &k)) continue;
    const VoxelInfo& info = index.info(index.lookup(k));
    float w = 1.f, fw = 1.f;
    if (info.known && !info.is_target) {
      if (!(info.p_occ > 0.5f)) continue;
      const float occupied = 1.f - info.prob[0];
      w = 0.f;
      fw = occupied > 0.f ? info.prob[fruit_cat] / occupied : 0.f;
      if (!(fw > 0.f)) continue;
    }
    kept.push_back(p);
    weights_.push_back(w);
    fruit_weights_.push_back(fw);
  }
  points_ = std::move(kept);
  // Each fruit's points in a sphere (their box's centre, the farthest point's distance).
  std::vector<Eigen::AlignedBox3d> boxes(fruits_.size());
  for (const PredictedPoint& p : points_) boxes[static_cast<std::size_t>(p.fruit)].extend(p.position);
  fruit_spheres_.assign(fruits_.size(), {Vec3::Zero(), -1.0});
  for (std::size_t f = 0; f < fruits_.size(); ++f)
    if (!boxes[f].isEmpty()) fruit_spheres_[f].first = boxes[f].center();
  for (const PredictedPoint& p : points_) {
    auto& [centre, radius] = fruit_spheres_[static_cast<std::size_t>(p.fruit)];
    radius = std::max(radius, (p.position - centre).norm());
  }
  fruit_info_.assign(fruits_.size(), Fruit{});
  for (const PredictedPoint& p : points_) ++fruit_info_[static_cast<std::size_t>(p.fruit)].unseen_points;
  for (std::size_t f = 0; f < fruits_.size(); ++f) {
    const FittedFruit& fr = fruits_[f];
    Fruit& fi = fruit_info_[f];
    double consistency = 0.0;
    int n = 0;
    Vec3 centroid = Vec3::Zero();
    LogoddsSums logodds;
    for (const Vec3& c : fr.points) {
      centroid += c;
      octomap::OcTreeKey k;
      if (!map.key_of(c, &k)) continue;
      if (const mapping::SemanticState* s = map.find(k)) logodds.add(*s, target);
      const VoxelInfo& info = index.info(index.lookup(k));
      const float occupied = 1.f - info.prob[0];
      if (occupied > 0.f) {
        consistency += info.prob[fruit_cat] / occupied;
        ++n;
      }
    }
    fi.label_consistency = n > 0 ? consistency / n : 0.0;
    if (!fr.points.empty()) {
      centroid /= double(fr.points.size());
      const Vec3 d = fr.shape.centre - centroid;
      if (d.norm() > 1e-6) fi.unseen_side = d.normalized();
    }
    const double total = ellipsoid_area(fr.shape.semi_axes) / (params_.spacing_m * params_.spacing_m);
    fi.seen = total > 0.0 ? std::clamp(1.0 - fi.unseen_points / total, 0.0, 1.0) : 0.0;
    fi.evidence = fruit_evidence(map, index, fruits_, f, logodds, fi.unseen_points, points_.size(), params_.fit);
  }
}

std::size_t ViewFeatures::ViewKeyHash::operator()(const ViewKey& k) const {
  std::uint64_t h = 1469598103934665603ULL;
  for (const std::uint64_t b : k) {
    h ^= b + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
    h *= 1099511628211ULL;
  }
  return static_cast<std::size_t>(h ^ (h >> 29));
}

int ViewFeatures::fruit_of(const Vec3& target) const {
  int best = -1;
  double best_d = 1e300;
  for (std::size_t f = 0; f < fruits_.size(); ++f) {
    const double d = (fruits_[f].shape.centre - target).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = int(f);
    }
  }
  return best;
}

void ViewFeatures::compute(const Pose& T, const Vec3& target, std::vector<float>* out) {
  CANOPY_CHECK(index_ && eval_, "ViewFeatures::compute before begin_round");
  out->clear();
  out->reserve(view_feature_names().size());
  // The ray sets' features read the map only through the voxels their rays visit: kept from an
  // earlier round while none of those voxels changed.
  if (ray_features_index_ != index_ || ray_features_.size() > 20000) {
    ray_features_.clear();
    ray_features_index_ = index_;
  }
  ViewKey key;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) std::memcpy(&key[std::size_t(3 * c + r)], &T.matrix()(r, c), 8);
  for (int a = 0; a < 3; ++a) std::memcpy(&key[std::size_t(12 + a)], &target[a], 8);
  RayFeatures* kept = nullptr;
  if (const auto it = ray_features_.find(key); it != ray_features_.end()) {
    RayFeatures& rf = it->second;
    if (!index_->changed_since(rf.generation, rf.bricks)) {
      rf.generation = index_->generation();  // checked up to now
      kept = &rf;
    }
  }
  if (kept) {
    ++rays_kept_;
    out->insert(out->end(), kept->values.begin(), kept->values.end());
  } else {
    ++rays_cast_;
    bricks_.clear();
    compute_rays(T, target, out);
    std::sort(bricks_.begin(), bricks_.end());
    bricks_.erase(std::unique(bricks_.begin(), bricks_.end()), bricks_.end());
    RayFeatures& rf = ray_features_[key];
    rf.values.assign(out->begin(), out->end());
    rf.bricks = bricks_;
    rf.generation = index_->generation();
  }
  compute_rest(T, target, out);
}

void ViewFeatures::compute_rays(const Pose& T, const Vec3& target, std::vector<float>* out) {
  const std::vector<const GainFunction*>& gains = gain_ptrs_;
  std::vector<double>& scores = scores_;
  scores.assign(gains.size(), 0.0);
  double blocked = 0, on_target = 0, unknown = 0, rays = 0;
  for (std::size_t r = 0; r < ray_sets_.size(); ++r) {
    std::function<void(const RayVoxel*, std::size_t)> each_ray;
    if (r == 0)
      each_ray = [&](const RayVoxel* v, std::size_t n) {
        ++rays;
        for (std::size_t i = 0; i < n; ++i) {
          const VoxelInfo& info = *v[i].info;
          if (!info.known) {
            ++unknown;
            continue;
          }
          if (info.p_occ > 0.5f) {
            (info.is_target ? on_target : blocked) += 1;
            break;
          }
        }
      };
    eval_->evaluate_all(T, target, gains, *ray_sets_[r], 0, scores.data(), each_ray, &bricks_);
    for (const double s : scores) out->push_back(static_cast<float>(s));
  }
  out->push_back(static_cast<float>(rays > 0 ? blocked / rays : 0.0));
  out->push_back(static_cast<float>(rays > 0 ? on_target / rays : 0.0));
  out->push_back(static_cast<float>(rays > 0 ? unknown / rays : 0.0));
}

void ViewFeatures::compute_rest(const Pose& T, const Vec3& target, std::vector<float>* out) {
  // The predicted surface in view (as the shape planner scores it).
  const int own = fruit_of(target);
  const Pose T_inv = T.inverse();
  const Vec3 eye = T.translation();
  const double res = index_->map()->getResolution();
  const std::size_t cap = index_->max_voxels(intrinsics_.max_range_m + 0.1);
  walk_capacity_ = std::max(walk_capacity_, cap);
  double seen = 0, seen_fp = 0, seen_own = 0, in_view = 0, zero = 0;
  // Fruits wholly out of view: their points would each fail the depth or image test below.
  fruit_out_of_view_.assign(fruits_.size(), 0);
  for (std::size_t f = 0; f < fruits_.size(); ++f)
    fruit_out_of_view_[f] = fruit_spheres_[f].second >= 0.0 &&
                            sphere_out_of_view(intrinsics_, T, fruit_spheres_[f].first, fruit_spheres_[f].second);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const PredictedPoint& pp = points_[i];
    if (fruit_out_of_view_[static_cast<std::size_t>(pp.fruit)]) continue;
    const Vec3& p = pp.position;
    const Vec3 to_eye = eye - p;
    if (to_eye.dot(pp.normal) <= 0.0) continue;
    const Vec3 c = T_inv * p;
    if (c.z() < intrinsics_.min_range_m || c.z() > intrinsics_.max_range_m) continue;
    double u = 0, v = 0;
    if (!intrinsics_.project(c, &u, &v) || u < 0.0 || v < 0.0 || u >= intrinsics_.width_px || v >= intrinsics_.height_px)
      continue;
    const double dist = to_eye.norm();
    if (dist <= res) continue;
    // The sight line's transmission from the eye, the walk stopped where it reaches (about)
    // zero: at its first occupied voxel, often well before the point.
    double t = 1.0;
    const bool inside = index_->walk(eye, p + to_eye * (res / dist), walk_capacity_, [&](const VoxelInfo& info) {
      if (!info.known) t *= params_.unknown_transmit;
      else if (info.p_occ > 0.5f) t = 0.0;
      return t > 1e-3;
    });
    if (!inside) continue;
    ++in_view;
    if (!(t > 1e-3)) {
      ++zero;
      continue;
    }
    seen += t * weights_[i];
    seen_fp += t * fruit_weights_[i];
    if (pp.fruit == own) seen_own += t * weights_[i];
  }
  out->push_back(static_cast<float>(seen));
  out->push_back(static_cast<float>(seen_fp));
  out->push_back(static_cast<float>(seen_own));
  out->push_back(static_cast<float>(in_view));
  out->push_back(static_cast<float>(in_view > 0 ? zero / in_view : 0.0));

  // The target fruit.
  const Vec3 view_dir = (eye - target).normalized();  // from the target toward the camera
  if (own >= 0) {
    const FittedFruit& f = fruits_[static_cast<std::size_t>(own)];
    const Fruit& fi = fruit_info_[static_cast<std::size_t>(own)];
    out->push_back(f.shape.ok ? 1.f : 0.f);
    out->push_back(static_cast<float>(1000.0 * f.shape.rms_m));
    out->push_back(static_cast<float>(f.points.size()));
    out->push_back(static_cast<float>(fi.seen));
    out->push_back(static_cast<float>(fi.label_consistency));
    out->push_back(static_cast<float>(fi.unseen_points));
  } else {
    for (int i = 0; i < 6; ++i) out->push_back(std::nanf(""));  // no fruit: missing, as XGBoost reads NaN
  }
  out->push_back(static_cast<float>(fruits_.size()));
  out->push_back(static_cast<float>(points_.size()));

  // Geometry.
  const Vec3 to_target = target - eye;
  const double dist = to_target.norm();
  const Vec3 axis = T.linear().col(2);
  out->push_back(static_cast<float>(dist));
  out->push_back(static_cast<float>(dist > 0 ? std::acos(std::clamp(axis.dot(to_target) / dist, -1.0, 1.0)) * 180.0 / M_PI : 0.0));
  out->push_back(static_cast<float>(eye.z() - target.z()));
  out->push_back(own >= 0 ? static_cast<float>(view_dir.dot(fruit_info_[static_cast<std::size_t>(own)].unseen_side))
                          : std::nanf(""));
  out->push_back(static_cast<float>((eye - T_now_.translation()).norm()));
  out->push_back(static_cast<float>(Eigen::AngleAxisd(T_now_.linear().transpose() * T.linear()).angle() * 180.0 / M_PI));

  // The target fruit's evidence.
  if (own >= 0) {
    const auto& e = fruit_info_[static_cast<std::size_t>(own)].evidence;
    out->insert(out->end(), e.begin(), e.end());
  } else {
    out->insert(out->end(), std::size(kEvidenceFeatures), std::nanf(""));
  }
  CANOPY_CHECK(out->size() == view_feature_names().size(), "one value per feature name");
}

}  // namespace canopy::nbv
