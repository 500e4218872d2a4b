#include "canopy/world/mesh.h"

#include <cmath>

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

}  // namespace canopy::world
