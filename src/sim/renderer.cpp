#include "canopy/sim/renderer.h"

#include <GL/osmesa.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
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

// A half-space n.x + d >= 0 (unit n).
struct HalfSpace {
  Vec3 n;
  double d;
  double at(const Vec3& x) const { return n.dot(x) + d; }
};
using Frustum = std::array<HalfSpace, 6>;

// The volume OpenGL rasterises for MuJoCo's symmetric perspective camera: the four sides
// through the eye at the viewport's edges and the near and far clip planes.
Frustum gl_frustum(const Vec3& eye, const Vec3& fwd, const Vec3& up, double near_m, double far_m, double top_over_near,
                   double right_over_near) {
  const Vec3 right = fwd.cross(up);
  auto through_eye = [&eye](const Vec3& n) {
    const Vec3 u = n.normalized();
    return HalfSpace{u, -u.dot(eye)};
  };
  return {through_eye(top_over_near * fwd - up), through_eye(top_over_near * fwd + up),
          through_eye(right_over_near * fwd - right), through_eye(right_over_near * fwd + right),
          HalfSpace{fwd, -fwd.dot(eye) - near_m}, HalfSpace{-fwd, fwd.dot(eye) + far_m}};
}

// True unless the capsule (segment a-b, radius r) lies wholly outside one of the half-spaces.
// Conservative: a capsule outside the frustum but not outside any single plane is kept.
bool may_touch(const Frustum& f, const Vec3& a, const Vec3& b, double r) {
  for (const HalfSpace& h : f)
    if (h.at(a) < -r && h.at(b) < -r) return false;
  return true;
}

Vec3 to_vec(const float* v) { return Vec3(v[0], v[1], v[2]); }

// Removes from the scene, keeping the others in their order, the geoms that cannot change a
// pixel of this frame: opaque model geoms whose bounding sphere lies outside the frustum and,
// when shadows are drawn, whose shadow cannot fall inside it either. Planes, transparent or
// reflective geoms and anything without a model bound are always kept (transparent geoms are
// depth-sorted, reflections show what is outside the frustum). Segmentation ids are renumbered
// to the new positions, so label decoding keeps indexing scene.geoms by segid.
void cull_outside(mjvScene& scene, const mjrContext& context, const Frustum& frustum, bool shadows) {
  // Bounds are padded by 1 mm and 0.01 % (float positions, rasterisation at the edges).
  constexpr double kPad = 1e-3, kRelPad = 1e-4;
  auto cullable = [](const mjvGeom& g) {
    return g.objtype == mjOBJ_GEOM && g.type != mjGEOM_PLANE && g.modelrbound > 0.f && g.rgba[3] >= 0.995f;
  };
  auto radius = [](const mjvGeom& g) { return g.modelrbound * (1.0 + kRelPad) + kPad; };
  // A reflecting geom mirrors what lies outside the frustum: draw everything.
  if (scene.flags[mjRND_REFLECTION])
    for (int i = 0; i < scene.ngeom; ++i) {
      const mjvGeom& g = scene.geoms[i];
      if ((g.type == mjGEOM_PLANE || g.type == mjGEOM_BOX) && g.rgba[3] >= 0.995f && g.reflectance > 0.f) return;
    }

  // Shadows (MuJoCo's shadow map, one per casting light). A geom darkens only points that lie
  // from it away from the light; for a directional light those are inside the sphere swept
  // along the light's direction down to the lowest point of the scene. The map covers a square
  // of half-side shadowClip around the light's axis; a geom reaching its border band is kept
  // (its edge texels may be sampled by points outside the map), one wholly outside it casts
  // nothing. Any other light, or one not shining downwards, turns culling off.
  struct Caster {
    Vec3 pos, dir;
  };
  std::vector<Caster> casters;
  double floor_z = std::numeric_limits<double>::infinity();
  double texel_pad = 0.0;
  if (shadows && context.shadowFBO) {
    for (int l = 0; l < scene.nlight; ++l) {
      const mjvLight& light = scene.lights[l];
      if (!light.castshadow) continue;
      const Vec3 dir = to_vec(light.dir).normalized();
      if (!light.directional || !(dir.z() < -0.05)) return;
      casters.push_back({to_vec(light.pos), dir});
    }
    for (int i = 0; i < scene.ngeom; ++i) {
      const mjvGeom& g = scene.geoms[i];
      if (g.type == mjGEOM_PLANE) {
        if (std::abs(g.mat[8]) < 1.f - 1e-6f) return;  // a tilted plane: no simple floor
        floor_z = std::min(floor_z, double(g.pos[2]));
      } else if (g.modelrbound > 0.f) {
        floor_z = std::min(floor_z, g.pos[2] - radius(g));
      } else {
        return;  // unbounded geometry
      }
    }
    texel_pad = 4.0 * 2.0 * context.shadowClip / std::max(1, context.shadowSize) + kPad;
  }

  auto shadow_may_touch = [&](const Vec3& c, double r) {
    for (const Caster& light : casters) {
      const Vec3 v = c - light.pos;
      const double perp = (v - v.dot(light.dir) * light.dir).norm();
      const double clip = context.shadowClip;
      if (perp - r > std::sqrt(2.0) * clip + texel_pad) continue;  // outside the map
      if (perp + r + texel_pad >= clip) return true;                // reaches the border band
      const double length = (c.z() - floor_z + r) / -light.dir.z();
      if (may_touch(frustum, c, c + std::max(0.0, length) * light.dir, r + texel_pad)) return true;
    }
    return false;
  };

  int kept = 0;
  for (int i = 0; i < scene.ngeom; ++i) {
    const mjvGeom& g = scene.geoms[i];
    bool keep = true;
    if (cullable(g)) {
      const Vec3 c = to_vec(g.pos);
      const double r = radius(g);
      keep = may_touch(frustum, c, c, r) || shadow_may_touch(c, r);
    }
    if (!keep) continue;
    if (kept != i) scene.geoms[kept] = g;
    if (scene.geoms[kept].segid >= 0) scene.geoms[kept].segid = kept;
    ++kept;
  }
  scene.ngeom = kept;
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
      noise_rng_(options.noise_seed), video_(intrinsics.width_px, intrinsics.height_px) {
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
  // MuJoCo halves the stacks for hemispheres and disks: fewer than 2 would draw none.
  if (options_.primitive_slices < 0 || (options_.primitive_slices > 0 && options_.primitive_slices < 3) ||
      options_.primitive_stacks < 0 || options_.primitive_stacks == 1)
    throw InputError("renderer: primitive slices must be 0 (the model's) or >= 3, stacks 0 or >= 2; got " +
                     std::to_string(options_.primitive_slices) + " and " + std::to_string(options_.primitive_stacks));
  slices_ = options_.primitive_slices > 0 ? options_.primitive_slices : m->vis.quality.numslices;
  stacks_ = options_.primitive_stacks > 0 ? options_.primitive_stacks : m->vis.quality.numstacks;
  make_model_context();
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

void Renderer::make_model_context() {
  Impl& r = *impl_;
  const mjModel* m = sim_.render_model();
  if (r.context_made) mjr_freeContext(&r.context);
  if (r.scene_made) mjv_freeScene(&r.scene);
  r.context_made = r.scene_made = false;
  mjv_defaultScene(&r.scene);
  mjr_defaultContext(&r.context);
  mjv_makeScene(m, &r.scene, m->ngeom + 64);
  r.scene_made = true;
  if (slices_ == m->vis.quality.numslices && stacks_ == m->vis.quality.numstacks) {
    mjr_makeContext(m, &r.context, mjFONTSCALE_50);
  } else {
    // The context's display lists come from a copy with the coarser tessellation; the scene
    // still draws the simulator's model (the same geoms, meshes and materials).
    std::unique_ptr<mjModel, void (*)(mjModel*)> coarse(mj_copyModel(nullptr, m), mj_deleteModel);
    if (!coarse) throw std::runtime_error("MuJoCo: cannot copy the model for the renderer");
    coarse->vis.quality.numslices = slices_;
    coarse->vis.quality.numstacks = stacks_;
    mjr_makeContext(coarse.get(), &r.context, mjFONTSCALE_50);
  }
  r.context_made = true;
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context);
  if (r.context.currentBuffer != mjFB_OFFSCREEN) throw std::runtime_error("MuJoCo: off-screen buffer not supported");
  generation_ = sim_.render_generation();
}

void Renderer::follow_model() {
  if (generation_ == sim_.render_generation()) return;
  make_model_context();
  video_.forget_world();
}

LabelledFrame Renderer::render_wrist_camera() {
  sim_.update_kinematics();
  return draw(sim_.camera_pose(), /*show_robot=*/true, /*labels=*/true);
}

void Renderer::warm_up() {
  const Pose T = sim_.camera_pose();
  if (!T.matrix().allFinite()) return;
  Impl& r = *impl_;
  std::unique_lock<std::mutex> lock(gl_mutex());
  r.make_current();
  follow_model();
  video_.forget_world();  // the GL buffers are reused
  pass(T, true, true, "", true);
  label_pass();
}

void Renderer::label_pass() {
  Impl& r = *impl_;
  const mjrRect viewport{0, 0, intrinsics_.width_px, intrinsics_.height_px};
  r.scene.flags[mjRND_SHADOW] = 0;
  r.scene.flags[mjRND_SKYBOX] = 0;
  r.scene.flags[mjRND_SEGMENT] = 1;
  r.scene.flags[mjRND_IDCOLOR] = 1;
  mjr_render(viewport, &r.scene, &r.context);
  mjr_readPixels(r.seg.data(), nullptr, viewport, &r.context);
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
  return draw(T_world_camera, show_robot, false, caption, /*depth=*/false).rgb;
}

Image<Rgb8> Renderer::render_video_frame(const Pose& T_world_camera, const std::string& caption) {
  sim_.update_kinematics();
  if (!T_world_camera.matrix().allFinite()) throw InputError("camera pose: not finite (NaN or inf)");
  Impl& r = *impl_;
  const int W = intrinsics_.width_px, H = intrinsics_.height_px;
  std::unique_lock<std::mutex> lock(gl_mutex());
  r.make_current();
  follow_model();  // a model built again: the kept world is forgotten (and drawn again)
  const bool still = video_.camera_still(T_world_camera, options_.shadows);
  Image<Rgb8> out(W, H);
  if (!still) {  // the camera moves: the whole scene
    video_.full_frame();
    pass(T_world_camera, true, true, caption, false);
  } else {
    robot_over_kept_world(T_world_camera, caption);
  }
  video_.end_frame(caption);
  const std::vector<unsigned char>& rgb = still ? video_.frame_rgb() : r.rgb;
  for (int y = 0; y < H; ++y)
    std::memcpy(static_cast<void*>(&out.at(0, y)), &rgb[3 * static_cast<size_t>(H - 1 - y) * W], 3 * static_cast<size_t>(W));
  return out;
}

void Renderer::robot_over_kept_world(const Pose& T_world_camera, const std::string& caption) {
  Impl& r = *impl_;
  const mjModel* m = sim_.render_model();
  const int W = intrinsics_.width_px, H = intrinsics_.height_px;
  const mjrRect whole{0, 0, W, H};
  bool redraw = false;
  if (!video_.has_world()) {  // the camera stopped: keep the world without the robot
    pass(T_world_camera, true, false, "", true);
    video_.keep_world(r.rgb, r.depth);
  }
  if (video_.needs_caption(caption)) {
    // The caption over the kept world, as mjr_overlay draws it after mjr_render.
    std::vector<unsigned char> captioned = video_.world_rgb();
    if (!caption.empty()) {
      glDisable(GL_DEPTH_TEST);
      mjr_drawPixels(video_.world_rgb().data(), nullptr, whole, &r.context);
      mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, whole, caption.c_str(), nullptr, &r.context);
      mjr_readPixels(captioned.data(), nullptr, whole, &r.context);
    }
    video_.set_captioned_world(std::move(captioned), caption);
    redraw = true;
  }

  r.option.geomgroup[kGroupGround] = 0;
  r.option.geomgroup[kGroupPlants] = 0;
  r.option.geomgroup[kGroupRobotVisual] = 1;
  mjv_updateScene(m, sim_.render_data(), &r.option, nullptr, &r.camera, mjCAT_ALL, &r.scene);
  if (!video_.robot_changed(r.scene, redraw)) return;
  const double near_m = m->vis.map.znear * m->stat.extent;
  const ScreenRect rect = video_.start_robot(r.scene, T_world_camera, intrinsics_.fy_px, near_m);
  if (video_.robot_rect_pixels() == 0) return;  // the robot is out of view
  pass(T_world_camera, false, true, video_.rect_meets_caption(rect) ? caption : "", true, &rect);
  video_.compose_robot(r.rgb, r.depth);
}

void Renderer::pass(const Pose& T_world_camera, bool world, bool show_robot, const std::string& caption, bool depth,
                    const std::array<int, 4>* rect, bool depth_only) {
  Impl& r = *impl_;
  const mjModel* m = sim_.render_model();
  const int W = intrinsics_.width_px, H = intrinsics_.height_px;
  r.option.geomgroup[kGroupGround] = world;
  r.option.geomgroup[kGroupPlants] = world;
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
    if (rect) {  // the part of the same frustum that the rectangle of pixels sees
      const double k = near_m / intrinsics_.fy_px;
      cam.frustum_bottom = static_cast<float>(k * ((*rect)[1] - 0.5 * H));
      cam.frustum_top = static_cast<float>(k * ((*rect)[1] + (*rect)[3] - 0.5 * H));
      cam.frustum_center = static_cast<float>(k * ((*rect)[0] + 0.5 * (*rect)[2] - 0.5 * W));
    }
  }
  scene_geoms_ = r.scene.ngeom;
  if (culling_)
    cull_outside(r.scene, r.context,
                 gl_frustum(p, fwd, up, near_m, far_m, 0.5 * H / intrinsics_.fy_px, 0.5 * W / intrinsics_.fy_px),
                 options_.shadows);
  drawn_geoms_ = r.scene.ngeom;
  last_triangles_ = 0;
  for (int g = 0; g < r.scene.ngeom; ++g) {
    const mjvGeom& geom = r.scene.geoms[g];
    if (geom.type == mjGEOM_MESH && geom.objtype == mjOBJ_GEOM && m->geom_dataid[geom.objid] >= 0)
      last_triangles_ += m->mesh_facenum[m->geom_dataid[geom.objid]];
    else if (geom.type == mjGEOM_BOX) last_triangles_ += 12;
    else if (geom.type == mjGEOM_PLANE) last_triangles_ += 2;
    else last_triangles_ += 2L * slices_ * stacks_;
  }

  const mjrRect whole{0, 0, W, H};
  const mjrRect viewport = rect ? mjrRect{(*rect)[0], (*rect)[1], (*rect)[2], (*rect)[3]} : whole;
  r.scene.flags[mjRND_SHADOW] = options_.shadows;
  r.scene.flags[mjRND_SKYBOX] = world;
  r.scene.flags[mjRND_SEGMENT] = 0;
  r.scene.flags[mjRND_IDCOLOR] = 0;
  // Lighting only shades the colours (llvmpipe computes it per vertex on the calling thread);
  // the geometry, depth test and depth values do not depend on it.
  const int lights = r.scene.nlight;
  if (depth_only) r.scene.nlight = 0;
  mjr_render(viewport, &r.scene, &r.context);
  r.scene.nlight = lights;
  // The caption where it falls in the whole frame (only the viewport's part is read back).
  if (!caption.empty()) mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, whole, caption.c_str(), nullptr, &r.context);
  mjr_readPixels(depth_only ? nullptr : r.rgb.data(), depth ? r.depth.data() : nullptr, viewport, &r.context);
}

Image<float> Renderer::render_depth(const Pose& T_world_camera) {
  sim_.update_kinematics();
  if (!T_world_camera.matrix().allFinite()) throw InputError("camera pose: not finite (NaN or inf)");
  Impl& r = *impl_;
  std::unique_lock<std::mutex> lock(gl_mutex());
  r.make_current();
  follow_model();
  video_.forget_world();  // the GL buffers are reused
  pass(T_world_camera, true, false, "", true, nullptr, /*depth_only=*/true);
  const mjModel* m = sim_.render_model();
  const double near_m = m->vis.map.znear * m->stat.extent, far_m = m->vis.map.zfar * m->stat.extent;
  lock.unlock();  // decoding touches only this renderer's buffers
  return decode_depth(near_m, far_m);
}

Image<float> Renderer::decode_depth(double near_m, double far_m) {
  const Impl& r = *impl_;
  const int W = intrinsics_.width_px, H = intrinsics_.height_px;
  const double near_over_far = near_m / far_m;
  const double noise_k = intrinsics_.depth_noise_k;
  Image<float> out(W, H, 0.f);
  for (int y = 0; y < H; ++y) {
    const int src_row = H - 1 - y;  // OpenGL rows are bottom-up
    for (int x = 0; x < W; ++x) {
      const double d = r.depth[static_cast<size_t>(src_row) * W + x];
      double z = d >= 1.0 ? far_m : near_m / (1.0 - d * (1.0 - near_over_far));
      if (noise_k > 0.0 && d < 1.0) z += noise_k * z * z * noise_rng_.normal();
      if (z >= intrinsics_.min_range_m && z <= intrinsics_.max_range_m) out.at(x, y) = static_cast<float>(z);
    }
  }
  return out;
}

LabelledFrame Renderer::draw(const Pose& T_world_camera, bool show_robot, bool labels, const std::string& caption,
                             bool depth) {
  Impl& r = *impl_;
  const int W = intrinsics_.width_px, H = intrinsics_.height_px;
  if (!T_world_camera.matrix().allFinite()) throw InputError("camera pose: not finite (NaN or inf)");
  std::unique_lock<std::mutex> lock(gl_mutex());
  r.make_current();
  follow_model();
  video_.forget_world();  // the GL buffers are reused
  pass(T_world_camera, true, show_robot, caption, depth);
  const mjModel* m = sim_.render_model();
  const double near_m = m->vis.map.znear * m->stat.extent;
  const double far_m = m->vis.map.zfar * m->stat.extent;
  if (labels) label_pass();

  lock.unlock();  // decoding below touches only this renderer's buffers

  LabelledFrame f;
  f.intrinsics = intrinsics_;
  f.T_world_camera = T_world_camera;
  f.rgb = Image<Rgb8>(W, H);
  if (!depth) {  // RGB only (video frames)
    for (int y = 0; y < H; ++y)
      std::memcpy(static_cast<void*>(&f.rgb.at(0, y)), &r.rgb[3 * static_cast<size_t>(H - 1 - y) * W], 3 * static_cast<size_t>(W));
    return f;
  }
  f.depth_m = decode_depth(near_m, far_m);
  f.class_id = Image<std::uint8_t>(W, H, 0);
  f.instance = Image<std::int32_t>(W, H, kNoInstance);
  for (int y = 0; y < H; ++y) {
    const int src_row = H - 1 - y;  // OpenGL rows are bottom-up
    for (int x = 0; x < W; ++x) {
      const size_t s = static_cast<size_t>(src_row) * W + x;
      f.rgb.at(x, y) = Rgb8{r.rgb[3 * s], r.rgb[3 * s + 1], r.rgb[3 * s + 2]};
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
