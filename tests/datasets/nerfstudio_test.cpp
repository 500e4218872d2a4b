// The nerfstudio export read back as a user of the dataset would: transforms.json and
// transforms_test.json loaded, a pixel's depth back-projected through the stored OpenGL
// camera-to-world matrix and intrinsics lands on the true plant surface (the world's meshes)
// within 1 mm; fruit pixels land on the mesh of the fruit their instance id names.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/datasets/nerfstudio.h"
#include "canopy/jobs/test_views.h"
#include "canopy/settings/settings.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/world_spec.h"

namespace fs = std::filesystem;

namespace canopy::datasets {
namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// The exact distance from a point to a mesh: every triangle whose bounding box lies no nearer
// than the best distance so far is skipped (its box's distance is a lower bound of its own).
struct MeshDistance {
  const world::TriMesh& mesh;
  std::vector<Eigen::AlignedBox3d> boxes;
  explicit MeshDistance(const world::TriMesh& m) : mesh(m) {
    boxes.reserve(m.faces.size());
    for (const auto& f : m.faces) {
      Eigen::AlignedBox3d b(m.vertices[f[0]]);
      b.extend(m.vertices[f[1]]);
      b.extend(m.vertices[f[2]]);
      boxes.push_back(b);
    }
  }
  double operator()(const Vec3& p) const {
    double best2 = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
      if (boxes[k].squaredExteriorDistance(p) >= best2) continue;
      const auto& f = mesh.faces[k];
      best2 = std::min(best2, (p - closest_on_triangle(p, mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]])).squaredNorm());
    }
    return std::sqrt(best2);
  }
};

struct Export {
  world::World world;
  fs::path dir;
  Export() : world(world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")))) {
    char tmpl[] = "/tmp/canopy_export_XXXXXX";
    dir = ::mkdtemp(tmpl);
    sim::Simulator sim(world, default_robot_config());
    sim::Renderer renderer(sim, world.spec.camera);
    DatasetExport ex(dir.string(), world.spec.classes, world.spec.camera);
    const std::vector<Pose> views = evaluation::ring_views(world);
    ex.add_train(renderer.render_free_camera(views[0]));
    ex.add_train(renderer.render_free_camera(views[3]));
    evaluation::RingViews ring;
    ring.azimuths = 2;
    ring.heights = {0.5};
    jobs::render_test_views(ex, sim, world, ring);
    ex.finish({{"command", "test"}});
  }
  ~Export() { fs::remove_all(dir); }
};

const Export& exported() {
  static const Export e;
  return e;
}

TEST(DatasetExport, BackProjectedDepthLandsOnTheTrueSurface) {
  const Export& e = exported();
  std::map<int, MeshDistance> fruit_mesh;
  world::TriMesh plant_mesh;
  for (const world::Plant& p : e.world.plants)
    for (const world::PlantPart& part : p.parts) {
      plant_mesh.append(part.mesh);
      if (part.instance_id != kNoInstance) fruit_mesh.emplace(part.instance_id, MeshDistance(part.mesh));
    }
  const MeshDistance plants(plant_mesh);
  int frames = 0;
  for (const char* file : {"transforms.json", "transforms_test.json"}) {
    const nlohmann::json t = nlohmann::json::parse(read_file((e.dir / file).string()));
    ASSERT_EQ(t["camera_model"], "OPENCV");
    const double fx = t["fl_x"], fy = t["fl_y"], cx = t["cx"], cy = t["cy"], scale = t["depth_unit_scale_factor"];
    const int w = t["w"], h = t["h"];
    ASSERT_FALSE(t["frames"].empty()) << file;
    for (const nlohmann::json& f : t["frames"]) {
      ++frames;
      Eigen::Matrix4d M;
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) M(r, c) = f["transform_matrix"][r][c];
      // A rigid camera-to-world matrix.
      const Eigen::Matrix3d R = M.topLeftCorner(3, 3);
      EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-9);
      EXPECT_NEAR(R.determinant(), 1.0, 1e-9);
      const Image<float> depth = read_npy_float32((e.dir / f["depth_npy_path"].get<std::string>()).string());
      const Image<std::uint16_t> depth_mm = read_png_gray16((e.dir / f["depth_file_path"].get<std::string>()).string());
      const Image<std::uint16_t> inst = read_png_gray16((e.dir / f["instance_path"].get<std::string>()).string());
      ASSERT_EQ(depth.width, w);
      ASSERT_EQ(depth.height, h);
      ASSERT_EQ(depth_mm.width, w);
      ASSERT_EQ(inst.height, h);
      int checked = 0, fruit_checked = 0;
      double worst = 0.0, worst_png = 0.0, worst_fruit = 0.0;
      for (int j = 3; j < h; j += 9)
        for (int i = 5; i < w; i += 9) {
          const double z = depth.at(i, j);
          if (z <= 0.0) continue;
          EXPECT_LE(std::abs(depth_mm.at(i, j) * scale - z), 0.0005 + 1e-9);
          // nerfstudio's convention: OpenGL camera axes, pixel centre at (i + 0.5, j + 0.5).
          auto back_project = [&](double zz) {
            const Eigen::Vector4d p_cam((i + 0.5 - cx) / fx * zz, -(j + 0.5 - cy) / fy * zz, -zz, 1.0);
            return Vec3((M * p_cam).head<3>());
          };
          const Vec3 p = back_project(z);
          if (p.z() < 0.005) continue;  // the ground plane and the concrete path (4 mm slab): not meshes of the world
          const int id = inst.at(i, j) - 1;
          if (id >= 0) {
            ASSERT_TRUE(fruit_mesh.count(id)) << "instance " << id;
            const double d = fruit_mesh.at(id)(p);
            worst_fruit = std::max(worst_fruit, d);
            ++fruit_checked;
          }
          worst = std::max(worst, plants(p));
          worst_png = std::max(worst_png, plants(back_project(depth_mm.at(i, j) * scale)));
          ++checked;
        }
      EXPECT_GT(checked, 20) << f["file_path"];
      EXPECT_LT(worst, 0.001) << f["file_path"];
      EXPECT_LT(worst_fruit, 0.001) << f["file_path"];
      EXPECT_LT(worst_png, 0.001) << f["file_path"] << " (millimetre depth)";
      std::printf("%s: %d plant pixels (%d fruit), worst %.3f mm (float), %.3f mm (PNG), fruit %.3f mm\n",
                  f["file_path"].get<std::string>().c_str(), checked, fruit_checked, worst * 1e3, worst_png * 1e3,
                  worst_fruit * 1e3);
    }
  }
  EXPECT_EQ(frames, 2 + 2 * 2);  // two training views; 2 azimuths x 1 height x 2 plants held out
}

TEST(DatasetExport, WritesTheClassTableAndEveryFile) {
  const Export& e = exported();
  const nlohmann::json c = nlohmann::json::parse(read_file((e.dir / "classes.json").string()));
  ASSERT_EQ(c["classes"].size(), e.world.spec.classes.names.size());
  EXPECT_EQ(c["classes"][2]["name"], "fruit");
  EXPECT_EQ(c["target"], "fruit");
  const nlohmann::json t = nlohmann::json::parse(read_file((e.dir / "transforms.json").string()));
  for (const nlohmann::json& f : t["frames"])
    for (const char* k : {"file_path", "depth_file_path", "depth_npy_path", "label_path", "instance_path"})
      EXPECT_TRUE(fs::is_regular_file(e.dir / f[k].get<std::string>())) << f[k];
  const Image<Rgb8> rgb = read_png_rgb((e.dir / t["frames"][0]["file_path"].get<std::string>()).string());
  EXPECT_EQ(rgb.width, e.world.spec.camera.width_px);
}

TEST(DatasetExport, NpyRoundTripAndBadFiles) {
  char tmpl[] = "/tmp/canopy_npy_XXXXXX";
  const fs::path d = ::mkdtemp(tmpl);
  Image<float> img(5, 3);
  for (std::size_t k = 0; k < img.data.size(); ++k) img.data[k] = 0.25f * float(k) - 1.0f;
  write_npy_float32((d / "a.npy").string(), img);
  const Image<float> back = read_npy_float32((d / "a.npy").string());
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.data, img.data);
  // The header (with its padding and newline) is a multiple of 64 bytes, as NumPy writes it.
  EXPECT_EQ((fs::file_size(d / "a.npy") - img.data.size() * 4) % 64, 0u);
  write_file_atomic((d / "bad.npy").string(), "not numpy");
  EXPECT_THROW(read_npy_float32((d / "bad.npy").string()), InputError);
  std::string cut = read_file((d / "a.npy").string());
  cut.pop_back();
  write_file_atomic((d / "cut.npy").string(), cut);
  EXPECT_THROW(read_npy_float32((d / "cut.npy").string()), InputError);
  fs::remove_all(d);
}

TEST(DatasetExport, OpenGlAxesAreTheOpticalAxesFlipped) {
  const Pose T = make_pose(Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized())));
  const Eigen::Matrix4d M = opengl_camera_to_world(T);
  // A point 0.5 m in front of the optical camera is at -Z 0.5 in OpenGL axes, the same world point.
  const Vec3 p_world = T * Vec3(0.1, 0.2, 0.5);
  const Eigen::Vector4d p_gl(0.1, -0.2, -0.5, 1.0);
  EXPECT_LT(((M * p_gl).head<3>() - p_world).norm(), 1e-12);
}

}  // namespace
}  // namespace canopy::datasets
