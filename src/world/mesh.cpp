#include "canopy/world/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <unordered_map>

#include "canopy/common/error.h"

namespace canopy::world {

void TriMesh::append(const TriMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& f : other.faces) faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
}

void TriMesh::transform(const Pose& T) {
  for (auto& v : vertices) v = T * v;
}

double TriMesh::area() const {
  double a = 0.0;
  for (const auto& f : faces)
    a += 0.5 * (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]).norm();
  return a;
}

double TriMesh::volume() const {
  double v = 0.0;
  for (const auto& f : faces) v += vertices[f[0]].dot(vertices[f[1]].cross(vertices[f[2]])) / 6.0;
  return v;
}

void TriMesh::bounds(Vec3* lo, Vec3* hi) const {
  CANOPY_CHECK(!vertices.empty(), "bounds of an empty mesh");
  *lo = *hi = vertices.front();
  for (const auto& v : vertices) {
    *lo = lo->cwiseMin(v);
    *hi = hi->cwiseMax(v);
  }
}

TriMesh make_tube(const std::vector<Vec3>& points, const std::vector<double>& radii, int sides) {
  CANOPY_CHECK(points.size() >= 2 && radii.size() == points.size() && sides >= 3, "bad tube");
  TriMesh m;
  const int n = static_cast<int>(points.size());
  // A frame transported along the polyline keeps the rings from twisting.
  Vec3 tangent = (points[1] - points[0]).normalized();
  Vec3 normal = tangent.unitOrthogonal();
  for (int i = 0; i < n; ++i) {
    Vec3 t;
    if (i == 0) t = points[1] - points[0];
    else if (i == n - 1) t = points[i] - points[i - 1];
    else t = (points[i + 1] - points[i]).normalized() + (points[i] - points[i - 1]).normalized();
    t.normalize();
    normal = (normal - normal.dot(t) * t).normalized();
    const Vec3 binormal = t.cross(normal);
    for (int k = 0; k < sides; ++k) {
      const double a = 2.0 * M_PI * k / sides;
      m.vertices.push_back(points[i] + radii[i] * (std::cos(a) * normal + std::sin(a) * binormal));
    }
    tangent = t;
  }
  for (int i = 0; i + 1 < n; ++i)
    for (int k = 0; k < sides; ++k) {
      const int a = i * sides + k, b = i * sides + (k + 1) % sides;
      const int c = a + sides, d = b + sides;
      m.faces.push_back({a, b, d});
      m.faces.push_back({a, d, c});
    }
  // End caps.
  const int c0 = static_cast<int>(m.vertices.size());
  m.vertices.push_back(points.front());
  const int c1 = static_cast<int>(m.vertices.size());
  m.vertices.push_back(points.back());
  for (int k = 0; k < sides; ++k) {
    m.faces.push_back({c0, (k + 1) % sides, k});
    m.faces.push_back({c1, (n - 1) * sides + k, (n - 1) * sides + (k + 1) % sides});
  }
  return m;
}

TriMesh make_lobed_revolution(const std::vector<Vec2>& profile_rz, int segments, int lobes, double lobe_depth) {
  CANOPY_CHECK(profile_rz.size() >= 3 && segments >= 3, "bad revolution profile");
  // profile_rz runs from the top pole (r = 0) to the bottom pole (r = 0), z decreasing.
  TriMesh m;
  const int n = static_cast<int>(profile_rz.size());
  m.vertices.push_back(Vec3(0, 0, profile_rz.front().y()));  // top pole
  for (int i = 1; i + 1 < n; ++i)
    for (int k = 0; k < segments; ++k) {
      const double a = 2.0 * M_PI * k / segments;
      const double lobe = 1.0 - lobe_depth * 0.5 * (1.0 - std::cos(lobes * a));
      const double r = profile_rz[i].x() * lobe;
      m.vertices.push_back(Vec3(r * std::cos(a), r * std::sin(a), profile_rz[i].y()));
    }
  const int bottom = static_cast<int>(m.vertices.size());
  m.vertices.push_back(Vec3(0, 0, profile_rz.back().y()));
  const int rings = n - 2;
  auto idx = [&](int ring, int k) { return 1 + ring * segments + (k % segments); };
  for (int k = 0; k < segments; ++k) m.faces.push_back({0, idx(0, k), idx(0, k + 1)});
  for (int i = 0; i + 1 < rings; ++i)
    for (int k = 0; k < segments; ++k) {
      m.faces.push_back({idx(i, k), idx(i + 1, k + 1), idx(i, k + 1)});
      m.faces.push_back({idx(i, k), idx(i + 1, k), idx(i + 1, k + 1)});
    }
  for (int k = 0; k < segments; ++k) m.faces.push_back({bottom, idx(rings - 1, k + 1), idx(rings - 1, k)});
  return m;
}

namespace {

// Triangles with less area are degenerate [m^2] (a 1 mm x 1 um sliver has 5e-10).
constexpr double kMinTriangleAreaM2 = 1e-12;

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ULL;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
    return static_cast<size_t>(h);
  }
};
CellKey cell_of(const Vec3& p, double cell) {
  return {static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell)),
          static_cast<std::int64_t>(std::floor(p.z() / cell))};
}

}  // namespace

TriMesh weld_triangles(const std::vector<std::array<Vec3, 3>>& soup, double tol, long* degenerate,
                       std::vector<size_t>* kept) {
  TriMesh m;
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  const double cell = std::max(tol, 1e-9);
  auto index_of = [&](const Vec3& p) {
    const CellKey c = cell_of(p, cell);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({c.x + dx, c.y + dy, c.z + dz});
          if (it == grid.end()) continue;
          for (int i : it->second)
            if ((m.vertices[static_cast<size_t>(i)] - p).norm() <= tol) return i;
        }
    const int i = static_cast<int>(m.vertices.size());
    m.vertices.push_back(p);
    grid[c].push_back(i);
    return i;
  };
  for (size_t k = 0; k < soup.size(); ++k) {
    const auto& t = soup[k];
    const std::array<int, 3> f = {index_of(t[0]), index_of(t[1]), index_of(t[2])};
    const Vec3 &a = m.vertices[static_cast<size_t>(f[0])], &b = m.vertices[static_cast<size_t>(f[1])],
               &c = m.vertices[static_cast<size_t>(f[2])];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || 0.5 * (b - a).cross(c - a).norm() < kMinTriangleAreaM2) {
      ++*degenerate;
      continue;
    }
    m.faces.push_back(f);
    if (kept) kept->push_back(k);
  }
  return m;
}

TriMesh compact(const TriMesh& in) {
  TriMesh out;
  std::vector<int> remap(in.vertices.size(), -1);
  for (const auto& f : in.faces) {
    std::array<int, 3> g{};
    for (int k = 0; k < 3; ++k) {
      int& r = remap[static_cast<size_t>(f[static_cast<size_t>(k)])];
      if (r < 0) {
        r = static_cast<int>(out.vertices.size());
        out.vertices.push_back(in.vertices[static_cast<size_t>(f[static_cast<size_t>(k)])]);
      }
      g[static_cast<size_t>(k)] = r;
    }
    out.faces.push_back(g);
  }
  return out;
}

TriMesh cluster_vertices(const TriMesh& in, double cell, std::vector<size_t>* kept) {
  std::unordered_map<CellKey, int, CellHash> cell_index;
  std::vector<Vec3> sum;
  std::vector<int> count, remap(in.vertices.size());
  for (size_t i = 0; i < in.vertices.size(); ++i) {
    const auto [it, fresh] = cell_index.try_emplace(cell_of(in.vertices[i], cell), static_cast<int>(sum.size()));
    if (fresh) {
      sum.push_back(Vec3::Zero());
      count.push_back(0);
    }
    sum[static_cast<size_t>(it->second)] += in.vertices[i];
    ++count[static_cast<size_t>(it->second)];
    remap[i] = it->second;
  }
  TriMesh out;
  for (size_t c = 0; c < sum.size(); ++c) out.vertices.push_back(sum[c] / count[c]);
  std::set<std::array<int, 3>> seen;
  if (kept) kept->clear();
  for (size_t k = 0; k < in.faces.size(); ++k) {
    const auto& f = in.faces[k];
    const std::array<int, 3> g = {remap[static_cast<size_t>(f[0])], remap[static_cast<size_t>(f[1])],
                                  remap[static_cast<size_t>(f[2])]};
    if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2]) continue;
    std::array<int, 3> key = g;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) continue;
    out.faces.push_back(g);
    if (kept) kept->push_back(k);
  }
  return compact(out);
}

}  // namespace canopy::world
