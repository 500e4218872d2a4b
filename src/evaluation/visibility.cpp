#include "canopy/evaluation/visibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "canopy/common/error.h"

namespace canopy::evaluation {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Slab test: does origin + t * dir, t in [0, max_t], meet the box?
bool ray_box(const Vec3& o, const Vec3& inv, const Vec3& lo, const Vec3& hi, double max_t) {
  double t0 = 0.0, t1 = max_t;
  for (int a = 0; a < 3; ++a) {
    double ta = (lo[a] - o[a]) * inv[a], tb = (hi[a] - o[a]) * inv[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Moeller-Trumbore, both faces; t of the hit or a negative value.
double ray_triangle(const Vec3& o, const Vec3& d, const std::array<Vec3, 3>& tri) {
  const Vec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
  const Vec3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return -1.0;
  const double inv = 1.0 / det;
  const Vec3 s = o - tri[0];
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Vec3 q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return e2.dot(q) * inv;
}

}  // namespace

std::vector<CameraPosition> hemming_positions() {
  std::vector<CameraPosition> out;
  for (double az : {-60.0, -30.0, 0.0, 30.0, 60.0}) out.push_back({"level_az" + std::to_string(int(az)), az, 90.0});
  for (double az : {-60.0, -30.0, 0.0, 30.0, 60.0}) out.push_back({"up30_az" + std::to_string(int(az)), az, 60.0});
  for (double az : {-30.0, 0.0, 30.0}) out.push_back({"down30_az" + std::to_string(int(az)), az, 120.0});
  out.push_back({"up60_az0", 0.0, 30.0});
  return out;
}

RayScene::RayScene(const world::World& world) {
  for (std::size_t i = 0; i < world.plants.size(); ++i) {
    const std::shared_ptr<const world::Plant> plant = world.plant(i);  // generated again when not held
    for (const auto& part : plant->parts) add_part(part.mesh, part.instance_id);
  }
  build();
}

RayScene::RayScene(const std::vector<world::TriMesh>& meshes) {
  for (const auto& m : meshes) add_part(m, static_cast<int>(parts_.size()));
  build();
}

void RayScene::build() {
  std::vector<Vec3> centroids(tris_.size());
  for (size_t i = 0; i < tris_.size(); ++i) centroids[i] = (tris_[i][0] + tris_[i][1] + tris_[i][2]) / 3.0;
  order_.resize(tris_.size());
  for (size_t i = 0; i < order_.size(); ++i) order_[i] = i;
  nodes_.clear();
  if (!tris_.empty()) build_node(0, order_.size(), centroids);
}

// Median split along the longest axis of the centroids' box, down to leaves of 8 triangles.
int RayScene::build_node(size_t begin, size_t end, const std::vector<Vec3>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Vec3 clo = lo, chi = hi;
  for (size_t i = begin; i < end; ++i) {
    for (const Vec3& v : tris_[order_[i]]) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    clo = clo.cwiseMin(centroids[order_[i]]);
    chi = chi.cwiseMax(centroids[order_[i]]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (end - begin <= 8) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const size_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](size_t a, size_t b) { return centroids[a][axis] < centroids[b][axis]; });
  const int left = build_node(begin, mid, centroids);
  const int right = build_node(mid, end, centroids);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

void RayScene::add_part(const world::TriMesh& mesh, int instance_id) {
  Part p;
  p.first = tris_.size();
  p.instance_id = instance_id;
  mesh.bounds(&p.lo, &p.hi);
  for (const auto& f : mesh.faces) {
    tris_.push_back({mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]});
    part_of_tri_.push_back(static_cast<int>(parts_.size()));
  }
  p.count = tris_.size() - p.first;
  parts_.push_back(p);
}

int RayScene::part_of_instance(int instance_id) const {
  for (size_t i = 0; i < parts_.size(); ++i)
    if (parts_[i].instance_id == instance_id) return static_cast<int>(i);
  return -1;
}

int RayScene::first_hit(const Vec3& origin, const Vec3& dir, double max_t, double* t_hit, int only_part) const {
  const double big = std::numeric_limits<double>::infinity();
  const Vec3 inv(dir.x() != 0.0 ? 1.0 / dir.x() : big, dir.y() != 0.0 ? 1.0 / dir.y() : big,
                 dir.z() != 0.0 ? 1.0 / dir.z() : big);
  int best = -1;
  double best_t = max_t;
  if (only_part >= 0) {
    const Part& p = parts_.at(static_cast<size_t>(only_part));
    if (ray_box(origin, inv, p.lo, p.hi, best_t))
      for (size_t k = p.first; k < p.first + p.count; ++k) {
        const double t = ray_triangle(origin, dir, tris_[k]);
        if (t > 1e-9 && t < best_t) {
          best_t = t;
          best = only_part;
        }
      }
  } else if (!nodes_.empty()) {
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[static_cast<size_t>(stack[--top])];
      if (!ray_box(origin, inv, n.lo, n.hi, best_t)) continue;
      if (n.left < 0) {
        for (size_t i = n.first; i < n.first + n.count; ++i) {
          const size_t k = order_[i];
          const double t = ray_triangle(origin, dir, tris_[k]);
          if (t > 1e-9 && t < best_t) {
            best_t = t;
            best = part_of_tri_[k];
          }
        }
      } else if (top + 2 <= 128) {
        stack[top++] = n.left;
        stack[top++] = n.right;
      }
    }
  }
  if (t_hit) *t_hit = best_t;
  return best;
}

FruitView view_fruit(const RayScene& scene, int fruit_part, const std::vector<Vec3>& points, const Vec3& eye,
                     double tolerance_m) {
  FruitView v;
  for (const Vec3& p : points) {
    const Vec3 d = p - eye;
    const double dist = d.norm();
    if (dist < 1e-6) continue;
    const Vec3 dir = d / dist;
    double t_own = 0.0;
    // Facing: the ray meets its own fruit first at the point itself (not on the near side).
    if (scene.first_hit(eye, dir, dist + tolerance_m, &t_own, fruit_part) < 0 || t_own < dist - tolerance_m) continue;
    ++v.facing_points;
    double t = 0.0;
    const int hit = scene.first_hit(eye, dir, dist - tolerance_m, &t);
    if (hit >= 0 && hit != fruit_part) ++v.hidden_points;
  }
  return v;
}

Vec3 camera_eye(const Vec3& target, const Vec3& toward_aisle, const Vec3& along_row, const CameraPosition& position,
                double distance_m) {
  const double az = position.azimuth_deg * kDeg, zen = position.zenith_deg * kDeg;
  // View direction (camera -> target): into the row, turned by the azimuth towards +along_row,
  // tilted by the zenith angle.
  const Vec3 view = std::sin(zen) * (std::cos(az) * (-toward_aisle) + std::sin(az) * along_row) +
                    std::cos(zen) * Vec3::UnitZ();
  return target - distance_m * view.normalized();
}

BestCombination best_combination(const std::vector<FruitVisibility>& fruits, int positions, int k) {
  BestCombination best;
  best.k = k;
  if (k <= 0 || k > positions || fruits.empty()) return best;
  std::vector<int> idx(k);
  for (int i = 0; i < k; ++i) idx[i] = i;
  int best_count = -1;
  while (true) {
    int count = 0;
    for (const auto& f : fruits) {
      bool seen = false;
      for (int i : idx) seen = seen || f.detectable[i];
      count += seen;
    }
    if (count > best_count) {
      best_count = count;
      best.positions = idx;
    }
    int i = k - 1;
    while (i >= 0 && idx[i] == positions - k + i) --i;
    if (i < 0) break;
    ++idx[i];
    for (int j = i + 1; j < k; ++j) idx[j] = idx[j - 1] + 1;
  }
  best.detectability = double(best_count) / fruits.size();
  return best;
}

VisibilityResult measure_visibility(const world::World& world, const VisibilityParams& params) {
  if (params.positions.empty()) throw InputError("visibility: no camera positions");
  VisibilityResult r;
  r.params = params;
  const RayScene scene(world);
  const Vec3 along(1.0, 0.0, 0.0);
  // Each fruit's row: by the side of the aisle its plant stands on.
  std::map<int, const world::Plant*> plant_of;
  for (const auto& p : world.plants) plant_of[p.index] = &p;
  struct Item {
    const world::FruitTruth* fruit;
    int row;
  };
  std::vector<Item> items;
  for (const auto& f : world.truth.fruits) {
    if (!f.target && !params.include_unripe) continue;
    auto it = plant_of.find(f.plant_index);
    const double y = it != plant_of.end() ? it->second->base_position.y() : f.center.y();
    items.push_back({&f, y >= 0.0 ? 0 : 1});
  }
  // Sections: a grid over each row's plane, as few tiles as cover the row's fruit centres,
  // centred on them; numbered in (row, along, up) order.
  double x0[2], z0[2];
  for (int row = 0; row < 2; ++row) {
    double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_z = lo_x, hi_z = -lo_x;
    for (const auto& it : items)
      if (it.row == row) {
        lo_x = std::min(lo_x, it.fruit->center.x());
        hi_x = std::max(hi_x, it.fruit->center.x());
        lo_z = std::min(lo_z, it.fruit->center.z());
        hi_z = std::max(hi_z, it.fruit->center.z());
      }
    const double nx = std::max(1.0, std::ceil((hi_x - lo_x) / params.section_width_m - 1e-9));
    const double nz = std::max(1.0, std::ceil((hi_z - lo_z) / params.section_height_m - 1e-9));
    x0[row] = 0.5 * (lo_x + hi_x) - 0.5 * nx * params.section_width_m;
    z0[row] = 0.5 * (lo_z + hi_z) - 0.5 * nz * params.section_height_m;
  }
  auto key_of = [&](const Item& it) {
    return std::make_tuple(it.row, std::lround(std::floor((it.fruit->center.x() - x0[it.row]) / params.section_width_m)),
                           std::lround(std::floor((it.fruit->center.z() - z0[it.row]) / params.section_height_m)));
  };
  std::map<std::tuple<int, long, long>, int> section_of;
  for (const auto& it : items) section_of[key_of(it)] = 0;
  for (auto& [key, id] : section_of) {
    const int row = std::get<0>(key);
    Section sec;
    sec.row = row;
    sec.center = Vec3(x0[row] + (std::get<1>(key) + 0.5) * params.section_width_m,
                      row == 0 ? world.spec.rows.row_offset_m : -world.spec.rows.row_offset_m,
                      z0[row] + (std::get<2>(key) + 0.5) * params.section_height_m);
    sec.toward_aisle = Vec3(0.0, row == 0 ? -1.0 : 1.0, 0.0);
    id = static_cast<int>(r.sections.size());
    r.sections.push_back(sec);
  }
  const int P = static_cast<int>(params.positions.size());
  for (size_t s = 0; s < r.sections.size(); ++s)
    for (int p = 0; p < P; ++p) {
      SectionCamera c;
      c.section = static_cast<int>(s);
      c.position = p;
      c.target = r.sections[s].center;
      c.eye = camera_eye(c.target, r.sections[s].toward_aisle, along, params.positions[p], params.distance_m);
      c.pose = look_at(c.eye, c.target);
      r.cameras.push_back(c);
    }
  std::vector<double> occ_sum(P, 0.0);
  std::vector<int> det_count(P, 0);
  for (const auto& it : items) {
    const world::FruitTruth& f = *it.fruit;
    FruitVisibility fv;
    fv.instance_id = f.instance_id;
    fv.plant_index = f.plant_index;
    fv.section = section_of.at(key_of(it));
    // Evenly subsampled surface points (every n-th: deterministic).
    std::vector<Vec3> pts;
    const size_t n = f.surface_points.size();
    const size_t want = static_cast<size_t>(std::max(1, params.points_per_fruit));
    const size_t step = std::max<size_t>(1, n / want);
    for (size_t i = 0; i < n; i += step) pts.push_back(f.surface_points[i]);
    const int part = scene.part_of_instance(f.instance_id);
    for (int p = 0; p < P; ++p) {
      const SectionCamera& cam = r.cameras[fv.section * P + p];
      FruitView v = part >= 0 ? view_fruit(scene, part, pts, cam.eye) : FruitView{};
      double u = 0, w = 0;
      v.in_image = params.camera.project(cam.pose.inverse() * f.center, &u, &w) && params.camera.in_image(u, w);
      const bool det = v.in_image && v.facing_points > 0 && v.occlusion() <= params.max_occlusion;
      fv.views.push_back(v);
      fv.detectable.push_back(det);
      occ_sum[p] += v.occlusion();
      det_count[p] += det;
    }
    r.fruits.push_back(std::move(fv));
  }
  const double n = std::max<size_t>(1, r.fruits.size());
  for (int p = 0; p < P; ++p) {
    r.detectability.push_back(det_count[p] / n);
    r.mean_occlusion.push_back(occ_sum[p] / n);
  }
  for (int k = 1; k <= std::min(5, P); ++k) r.best.push_back(best_combination(r.fruits, P, k));
  return r;
}

}  // namespace canopy::evaluation
