#include "canopy/sim/renderer.h"

#include <GL/osmesa.h>

#include <cmath>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::sim {

namespace {
// OSMesa (llvmpipe) with MuJoCo's GL loader is not safe to drive from two threads at once:
// concurrent draws crashed inside libOSMesa after ~80 ablation jobs. Every context creation,
// draw and destruction in the process takes this lock; drawing is a small part of a
// planning step, so worker threads still overlap everything else.
std::mutex& gl_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace

struct Renderer::Impl {
  OSMesaContext gl = nullptr;
  std::vector<unsigned char> gl_buffer;
  mjvScene scene;
  mjvOption option;
  mjvCamera camera;
  mjrContext context;
  std::vector<unsigned char> rgb, seg;
  std::vector<float> depth;
  bool scene_made = false, context_made = false;
  int width = 0, height = 0;

  void make_current() {
    if (!OSMesaMakeCurrent(gl, gl_buffer.data(), GL_UNSIGNED_BYTE, width, height))
      throw std::runtime_error("OSMesa: cannot make the context current");
  }
  // Frees whatever was created, also when the Renderer constructor threw half-way.
  ~Impl() {
    std::lock_guard<std::mutex> lock(gl_mutex());
    if (gl) OSMesaMakeCurrent(gl, gl_buffer.data(), GL_UNSIGNED_BYTE, width, height);
    if (context_made) mjr_freeContext(&context);
    if (scene_made) mjv_freeScene(&scene);
    if (gl) OSMesaDestroyContext(gl);
  }
};

Renderer::Renderer(Simulator& sim, const CameraIntrinsics& intrinsics, const RenderOptions& options)
    : impl_(std::make_unique<Impl>()), sim_(sim), intrinsics_(intrinsics), options_(options),
      noise_rng_(options.noise_seed) {
  intrinsics_.validate("camera");
  const mjModel* m = sim_.render_model();
  if (m->vis.global.offwidth < intrinsics_.width_px || m->vis.global.offheight < intrinsics_.height_px)
    throw InputError("camera: " + std::to_string(intrinsics_.width_px) + "x" + std::to_string(intrinsics_.height_px) +
                     " exceeds the scene's off-screen buffer " + std::to_string(m->vis.global.offwidth) + "x" +
                     std::to_string(m->vis.global.offheight));
  install_mujoco_error_handler();
  std::lock_guard<std::mutex> lock(gl_mutex());
  Impl& r = *impl_;
  r.gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (!r.gl) throw std::runtime_error("OSMesa: cannot create a context");
  // The window-system buffer is unused (MuJoCo renders into its own offscreen FBO).
  r.width = intrinsics_.width_px;
  r.height = intrinsics_.height_px;
  r.gl_buffer.assign(static_cast<size_t>(4 * r.width * r.height), 0);
  r.make_current();
  mjv_defaultScene(&r.scene);
  mjv_defaultOption(&r.option);
  mjv_defaultCamera(&r.camera);
  mjr_defaultContext(&r.context);
  mjv_makeScene(m, &r.scene, m->ngeom + 64);
  r.scene_made = true;
  mjr_makeContext(m, &r.context, mjFONTSCALE_50);
  r.context_made = true;
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context);
  if (r.context.currentBuffer != mjFB_OFFSCREEN) throw std::runtime_error("MuJoCo: off-screen buffer not supported");
  // Only ground, plants and (optionally) the robot's visual geoms; no sites, frames or lights.
  for (int g = 0; g < mjNGROUP; ++g) {
    r.option.geomgroup[g] = g == kGroupGround || g == kGroupPlants || g == kGroupRobotVisual;
    r.option.sitegroup[g] = 0;
  }
  const size_t n = static_cast<size_t>(intrinsics_.width_px) * intrinsics_.height_px;
  r.rgb.resize(3 * n);
  r.seg.resize(3 * n);
  r.depth.resize(n);
}

Renderer::~Renderer() = default;

LabelledFrame Renderer::render_wrist_camera() {
  sim_.update_kinematics();
  return draw(sim_.camera_pose(), /*show_robot=*/true, /*labels=*/true);
}

LabelledFrame Renderer::render_free_camera(const Pose& T_world_camera) {
  return render(T_world_camera, /*show_robot=*/false);
}

LabelledFrame Renderer::render(const Pose& T_world_camera, bool show_robot, bool labels) {
  sim_.update_kinematics();
  return draw(T_world_camera, show_robot, labels);
}

Image<Rgb8> Renderer::render_captioned(const Pose& T_world_camera, bool show_robot, const std::string& caption) {
  sim_.update_kinematics();
  return draw(T_world_camera, show_robot, false, caption).rgb;
}

LabelledFrame Renderer::draw(const Pose& T_world_camera, bool show_robot, bool labels, const std::string& caption) {
  Impl& r = *impl_;
  const mjModel* m = sim_.render_model();
  const int W = intrinsics_.width_px, H = intrinsics_.height_px;
  if (!T_world_camera.matrix().allFinite()) throw InputError("camera pose: not finite (NaN or inf)");
  std::unique_lock<std::mutex> lock(gl_mutex());
  r.make_current();
  r.option.geomgroup[kGroupRobotVisual] = show_robot;
  mjv_updateScene(m, sim_.render_data(), &r.option, nullptr, &r.camera, mjCAT_ALL, &r.scene);

  // Place the GL camera at the optical frame: forward = +z, up = -y.
  const double near_m = m->vis.map.znear * m->stat.extent;
  const double far_m = m->vis.map.zfar * m->stat.extent;
  const Vec3 p = T_world_camera.translation();
  const Vec3 fwd = T_world_camera.linear().col(2);
  const Vec3 up = -T_world_camera.linear().col(1);
  for (int c = 0; c < 2; ++c) {
    mjvGLCamera& cam = r.scene.camera[c];
    for (int i = 0; i < 3; ++i) {
      cam.pos[i] = static_cast<float>(p[i]);
      cam.forward[i] = static_cast<float>(fwd[i]);
      cam.up[i] = static_cast<float>(up[i]);
    }
    cam.frustum_near = static_cast<float>(near_m);
    cam.frustum_far = static_cast<float>(far_m);
    cam.frustum_top = static_cast<float>(near_m * 0.5 * H / intrinsics_.fy_px);
    cam.frustum_bottom = -cam.frustum_top;
    cam.frustum_center = 0.f;
  }
  last_triangles_ = 0;
  for (int g = 0; g < r.scene.ngeom; ++g) {
    const mjvGeom& geom = r.scene.geoms[g];
    if (geom.type == mjGEOM_MESH && geom.objtype == mjOBJ_GEOM && m->geom_dataid[geom.objid] >= 0)
      last_triangles_ += m->mesh_facenum[m->geom_dataid[geom.objid]];
    else if (geom.type == mjGEOM_BOX) last_triangles_ += 12;
    else if (geom.type == mjGEOM_PLANE) last_triangles_ += 2;
    else last_triangles_ += 2L * m->vis.quality.numslices * m->vis.quality.numstacks;
  }

  const mjrRect viewport{0, 0, W, H};
  r.scene.flags[mjRND_SHADOW] = options_.shadows;
  r.scene.flags[mjRND_SKYBOX] = 1;
  r.scene.flags[mjRND_SEGMENT] = 0;
  r.scene.flags[mjRND_IDCOLOR] = 0;
  mjr_render(viewport, &r.scene, &r.context);
  if (!caption.empty()) mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, caption.c_str(), nullptr, &r.context);
  mjr_readPixels(r.rgb.data(), r.depth.data(), viewport, &r.context);
  if (labels) {
    r.scene.flags[mjRND_SHADOW] = 0;
    r.scene.flags[mjRND_SKYBOX] = 0;
    r.scene.flags[mjRND_SEGMENT] = 1;
    r.scene.flags[mjRND_IDCOLOR] = 1;
    mjr_render(viewport, &r.scene, &r.context);
    mjr_readPixels(r.seg.data(), nullptr, viewport, &r.context);
  }

  lock.unlock();  // decoding below touches only this renderer's buffers

  LabelledFrame f;
  f.intrinsics = intrinsics_;
  f.T_world_camera = T_world_camera;
  f.rgb = Image<Rgb8>(W, H);
  f.depth_m = Image<float>(W, H, 0.f);
  f.class_id = Image<std::uint8_t>(W, H, 0);
  f.instance = Image<std::int32_t>(W, H, kNoInstance);
  const double near_over_far = near_m / far_m;
  const double noise_k = intrinsics_.depth_noise_k;
  for (int y = 0; y < H; ++y) {
    const int src_row = H - 1 - y;  // OpenGL rows are bottom-up
    for (int x = 0; x < W; ++x) {
      const size_t s = static_cast<size_t>(src_row) * W + x;
      f.rgb.at(x, y) = Rgb8{r.rgb[3 * s], r.rgb[3 * s + 1], r.rgb[3 * s + 2]};
      const double d = r.depth[s];
      double z = d >= 1.0 ? far_m : near_m / (1.0 - d * (1.0 - near_over_far));
      if (noise_k > 0.0 && d < 1.0) z += noise_k * z * z * noise_rng_.normal();
      if (z >= intrinsics_.min_range_m && z <= intrinsics_.max_range_m) f.depth_m.at(x, y) = static_cast<float>(z);
      if (labels) {
        const int segid = r.seg[3 * s] + 256 * r.seg[3 * s + 1] + 65536 * r.seg[3 * s + 2] - 1;
        if (segid >= 0 && segid < r.scene.ngeom) {
          const mjvGeom& geom = r.scene.geoms[segid];
          if (geom.objtype == mjOBJ_GEOM && geom.objid >= 0) {
            const GeomLabel& label = sim_.geom_label(geom.objid);
            f.class_id.at(x, y) = static_cast<std::uint8_t>(label.class_id);
            f.instance.at(x, y) = label.instance_id;
            if (label.robot && options_.self_filter) f.depth_m.at(x, y) = 0.f;
          }
        }
      }
    }
  }
  return f;
}

}  // namespace canopy::sim
