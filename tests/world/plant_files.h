#pragma once
// Plant model files the import tests write themselves (no third-party meshes in the repo):
// a stem (box), a flat leaf, a degenerate sliver, two fruit cubes and a small fruit fragment
// beside the first, in inches with +z up; as COLLADA (two styles of unit) and as OBJ + MTL.

#include <array>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace canopy::test_plant {

using P = std::array<double, 3>;
using Tri = std::array<P, 3>;

constexpr double kInch = 0.0254;
constexpr double kHeightIn = 40.0;          // stem top
constexpr double kBaseXIn = 10.0, kBaseYIn = 5.0;
constexpr double kFruitSideIn = 3.0;
const P kFruitA = {14.0, 5.0, 20.0}, kFruitB = {5.0, 5.0, 25.0};  // cube centres [in]

inline std::vector<Tri> box(P lo, P hi) {
  auto v = [&](int i) { return P{(i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]}; };
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Tri> out;
  for (const auto& f : q) {
    out.push_back({v(f[0]), v(f[1]), v(f[2])});
    out.push_back({v(f[0]), v(f[2]), v(f[3])});
  }
  return out;
}
inline std::vector<Tri> cube(P c, double side) {
  const double h = 0.5 * side;
  return box({c[0] - h, c[1] - h, c[2] - h}, {c[0] + h, c[1] + h, c[2] + h});
}

/// Leaf-class triangles [in]: stem box, a flat leaf quad and one degenerate (collinear) sliver.
inline std::vector<Tri> leaf_triangles() {
  std::vector<Tri> t = box({kBaseXIn - 0.5, kBaseYIn - 0.5, 0.0}, {kBaseXIn + 0.5, kBaseYIn + 0.5, kHeightIn});
  t.push_back({P{10.5, 4, 30}, P{20, 4, 30}, P{20, 6, 30}});
  t.push_back({P{10.5, 4, 30}, P{20, 6, 30}, P{10.5, 6, 30}});
  t.push_back({P{11, 5, 31}, P{12, 5, 31}, P{13, 5, 31}});  // zero area
  return t;
}
/// Fruit A with a 0.2 in fragment 0.2 in above it (merged), and fruit B.
inline std::vector<Tri> fruit_a_triangles() {
  std::vector<Tri> t = cube(kFruitA, kFruitSideIn);
  for (const auto& f : cube({kFruitA[0], kFruitA[1], kFruitA[2] + 1.8}, 0.2)) t.push_back(f);
  return t;
}
inline std::vector<Tri> fruit_b_triangles() { return cube(kFruitB, kFruitSideIn); }

struct Group {
  std::string material;  // also the symbol
  std::array<double, 3> rgb;
  std::vector<Tri> tris;
};

/// The plant's material groups: leaf, ripe fruit (A and, unless `b_unripe`, B), unripe fruit.
inline std::vector<Group> groups(bool b_unripe) {
  std::vector<Group> g = {{"Capsicum_lef", {0.2, 0.6, 0.1}, leaf_triangles()},
                          {"Capsicum_frt1", {0.8, 0.1, 0.05}, fruit_a_triangles()}};
  if (b_unripe) g.push_back({"Capsicum_frt0", {0.6, 0.7, 0.1}, fruit_b_triangles()});
  else
    for (const auto& t : fruit_b_triangles()) g[1].tris.push_back(t);
  return g;
}

/// COLLADA, Z-up, one geometry in material groups. new_style: <unit> is 1 m and the node
/// matrix scales by 0.0254; otherwise <unit> is 0.0254 m and two nodes instance the geometry
/// (doubled, as older community files do).
inline std::string collada(bool new_style, bool b_unripe = false) {
  const std::vector<Group> gs = groups(b_unripe);
  std::ostringstream o;
  o.precision(17);
  o << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
    << "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
    << "<asset><unit name=\"" << (new_style ? "meter\" meter=\"1" : "inch\" meter=\"0.0254")
    << "\"/><up_axis>Z_UP</up_axis></asset>\n<library_effects>\n";
  for (const auto& g : gs)
    o << "<effect id=\"e_" << g.material << "\"><profile_COMMON><technique sid=\"common\"><lambert><diffuse><color>"
      << g.rgb[0] << " " << g.rgb[1] << " " << g.rgb[2] << " 1</color></diffuse></lambert></technique></profile_COMMON></effect>\n";
  o << "</library_effects>\n<library_materials>\n";
  for (const auto& g : gs)
    o << "<material id=\"m_" << g.material << "\" name=\"" << g.material << "\"><instance_effect url=\"#e_" << g.material
      << "\"/></material>\n";
  o << "</library_materials>\n<library_geometries><geometry id=\"plant\" name=\"plant\"><mesh>\n";
  size_t n = 0;
  for (const auto& g : gs) n += 3 * g.tris.size();
  o << "<source id=\"pos\"><float_array id=\"pos-a\" count=\"" << 3 * n << "\">";
  for (const auto& g : gs)
    for (const auto& t : g.tris)
      for (const auto& p : t) o << p[0] << " " << p[1] << " " << p[2] << " ";
  o << "</float_array><technique_common><accessor source=\"#pos-a\" count=\"" << n
    << "\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" "
       "type=\"float\"/></accessor></technique_common></source>\n"
    << "<vertices id=\"verts\"><input semantic=\"POSITION\" source=\"#pos\"/></vertices>\n";
  size_t base = 0;
  for (const auto& g : gs) {
    o << "<triangles material=\"" << g.material << "\" count=\"" << g.tris.size()
      << "\"><input semantic=\"VERTEX\" source=\"#verts\" offset=\"0\"/><p>";
    for (size_t i = 0; i < 3 * g.tris.size(); ++i) o << base + i << " ";
    base += 3 * g.tris.size();
    o << "</p></triangles>\n";
  }
  o << "</mesh></geometry></library_geometries>\n<library_visual_scenes><visual_scene id=\"scene\">\n";
  auto node = [&](const std::string& name, double s) {
    o << "<node id=\"" << name << "\" name=\"" << name << "\"><matrix>" << s << " 0 0 0 0 " << s << " 0 0 0 0 " << s
      << " 0 0 0 0 1</matrix><instance_geometry url=\"#plant\"><bind_material><technique_common>";
    for (const auto& g : gs)
      o << "<instance_material symbol=\"" << g.material << "\" target=\"#m_" << g.material << "\"/>";
    o << "</technique_common></bind_material></instance_geometry></node>\n";
  };
  if (new_style) {
    node("plant_node", kInch);
  } else {
    node("plant_node", 1.0);
    node("plant_node_copy", 1.0);
  }
  o << "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#scene\"/></scene>\n</COLLADA>\n";
  return o.str();
}

/// An uncompressed 24-bit TGA (rows stored top first): the top `top_rows` rows `top`, the
/// rest `bottom`.
inline void write_tga(const std::string& path, int w, int h, int top_rows, std::array<unsigned char, 3> top,
                      std::array<unsigned char, 3> bottom) {
  std::string b(18, '\0');
  b[2] = 2;  // uncompressed true colour
  b[12] = static_cast<char>(w & 255), b[13] = static_cast<char>(w >> 8);
  b[14] = static_cast<char>(h & 255), b[15] = static_cast<char>(h >> 8);
  b[16] = 24;
  b[17] = 0x20;  // origin at the top left
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto& c = y < top_rows ? top : bottom;
      b += static_cast<char>(c[2]), b += static_cast<char>(c[1]), b += static_cast<char>(c[0]);  // BGR
    }
  std::ofstream(path, std::ios::binary) << b;
}

/// UV rectangle [u0, u1] x [v0, v1] of a material group of the textured plant: fruit use
/// only the upper part of their texture (v >= 0.55: the image's top rows), leaves all of it.
inline std::array<double, 4> uv_rect(const std::string& material) {
  if (material.find("frt") != std::string::npos) return {0.05, 0.95, 0.55, 0.95};
  return {0.0, 1.0, 0.0, 1.0};
}

/// The plant of collada(true, b_unripe) with white diffuse colours and a diffuse texture per
/// material, "<material>.tga" beside the file (write them with write_tga), and texture
/// coordinates on every triangle: the two triangles of each box face span uv_rect.
inline std::string collada_textured(bool b_unripe = false) {
  const std::vector<Group> gs = groups(b_unripe);
  std::ostringstream o;
  o.precision(17);
  o << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
    << "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
    << "<asset><unit name=\"meter\" meter=\"1\"/><up_axis>Z_UP</up_axis></asset>\n<library_images>\n";
  for (const auto& g : gs)
    o << "<image id=\"img_" << g.material << "\" name=\"img_" << g.material << "\"><init_from>" << g.material
      << ".tga</init_from></image>\n";
  o << "</library_images>\n<library_effects>\n";
  for (const auto& g : gs)
    o << "<effect id=\"e_" << g.material << "\"><profile_COMMON><newparam sid=\"s_" << g.material
      << "\"><surface type=\"2D\"><init_from>img_" << g.material << "</init_from></surface></newparam><newparam sid=\"t_"
      << g.material << "\"><sampler2D><source>s_" << g.material
      << "</source></sampler2D></newparam><technique sid=\"common\"><lambert><diffuse><texture texture=\"t_" << g.material
      << "\" texcoord=\"UVSET0\"/></diffuse></lambert></technique></profile_COMMON></effect>\n";
  o << "</library_effects>\n<library_materials>\n";
  for (const auto& g : gs)
    o << "<material id=\"m_" << g.material << "\" name=\"" << g.material << "\"><instance_effect url=\"#e_" << g.material
      << "\"/></material>\n";
  o << "</library_materials>\n<library_geometries><geometry id=\"plant\" name=\"plant\"><mesh>\n";
  size_t n = 0;
  for (const auto& g : gs) n += 3 * g.tris.size();
  o << "<source id=\"pos\"><float_array id=\"pos-a\" count=\"" << 3 * n << "\">";
  for (const auto& g : gs)
    for (const auto& t : g.tris)
      for (const auto& p : t) o << p[0] << " " << p[1] << " " << p[2] << " ";
  o << "</float_array><technique_common><accessor source=\"#pos-a\" count=\"" << n
    << "\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" "
       "type=\"float\"/></accessor></technique_common></source>\n";
  o << "<source id=\"uv\"><float_array id=\"uv-a\" count=\"" << 2 * n << "\">";
  for (const auto& g : gs) {
    const auto r = uv_rect(g.material);
    const double corner[4][2] = {{r[0], r[2]}, {r[1], r[2]}, {r[1], r[3]}, {r[0], r[3]}};
    for (size_t t = 0; t < g.tris.size(); ++t) {
      const int c[2][3] = {{0, 1, 2}, {0, 2, 3}};
      for (int k = 0; k < 3; ++k) o << corner[c[t % 2][k]][0] << " " << corner[c[t % 2][k]][1] << " ";
    }
  }
  o << "</float_array><technique_common><accessor source=\"#uv-a\" count=\"" << n
    << "\" stride=\"2\"><param name=\"S\" type=\"float\"/><param name=\"T\" type=\"float\"/></accessor>"
       "</technique_common></source>\n"
    << "<vertices id=\"verts\"><input semantic=\"POSITION\" source=\"#pos\"/></vertices>\n";
  size_t base = 0;
  for (const auto& g : gs) {
    o << "<triangles material=\"" << g.material << "\" count=\"" << g.tris.size()
      << "\"><input semantic=\"VERTEX\" source=\"#verts\" offset=\"0\"/><input semantic=\"TEXCOORD\" source=\"#uv\" "
         "offset=\"1\" set=\"0\"/><p>";
    for (size_t i = 0; i < 3 * g.tris.size(); ++i) o << base + i << " " << base + i << " ";
    base += 3 * g.tris.size();
    o << "</p></triangles>\n";
  }
  o << "</mesh></geometry></library_geometries>\n<library_visual_scenes><visual_scene id=\"scene\">\n"
    << "<node id=\"plant_node\" name=\"plant_node\"><matrix>" << kInch << " 0 0 0 0 " << kInch << " 0 0 0 0 " << kInch
    << " 0 0 0 0 1</matrix><instance_geometry url=\"#plant\"><bind_material><technique_common>";
  for (const auto& g : gs)
    o << "<instance_material symbol=\"" << g.material << "\" target=\"#m_" << g.material
      << "\"><bind_vertex_input semantic=\"UVSET0\" input_semantic=\"TEXCOORD\" input_set=\"0\"/></instance_material>";
  o << "</technique_common></bind_material></instance_geometry></node>\n"
    << "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#scene\"/></scene>\n</COLLADA>\n";
  return o.str();
}

/// The same plant as OBJ + MTL, in metres and Y-up (x, z, -y), as OBJ files usually are.
inline void write_obj(const std::string& obj_path, const std::string& mtl_name, bool b_unripe = false) {
  const std::vector<Group> gs = groups(b_unripe);
  std::ofstream mtl(obj_path.substr(0, obj_path.find_last_of('/') + 1) + mtl_name);
  for (const auto& g : gs) mtl << "newmtl " << g.material << "\nKd " << g.rgb[0] << " " << g.rgb[1] << " " << g.rgb[2] << "\n";
  std::ofstream obj(obj_path);
  obj.precision(17);
  obj << "mtllib " << mtl_name << "\n";
  int v = 1;
  for (const auto& g : gs) {
    obj << "usemtl " << g.material << "\n";
    for (const auto& t : g.tris) {
      for (const auto& p : t) obj << "v " << p[0] * kInch << " " << p[2] * kInch << " " << -p[1] * kInch << "\n";
      obj << "f " << v << " " << v + 1 << " " << v + 2 << "\n";
      v += 3;
    }
  }
}

inline void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace canopy::test_plant
