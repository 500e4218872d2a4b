#pragma once
// Headless off-screen rendering with OSMesa (no display, no GPU): RGB, metric z-depth and
// per-pixel semantic class and fruit instance, from the wrist camera or a free camera.

#include <array>
#include <memory>
#include <vector>
#include <string>

#include "canopy/common/frame.h"
#include "canopy/common/random.h"
#include "canopy/sim/simulator.h"
#include "canopy/sim/video_frame_cache.h"

namespace canopy::sim {

/// Rendering switches. Anti-aliasing is always off (labels must not blend).
struct RenderOptions {
  bool shadows = false;         ///< Shadows in the RGB pass only (they cost 3-4x).
  std::uint64_t noise_seed = 1; ///< Seed of the depth noise (CameraIntrinsics::depth_noise_k).
  /// Robot self-filter: pixels showing the robot itself get no depth (as a real RGB-D
  /// pipeline masks the robot out), so a map built from the wrist camera never holds the
  /// robot. Needs the segmentation pass (labels).
  bool self_filter = false;
  /// Tessellation of MuJoCo's cylinders, capsules and spheres (slices around, stacks along);
  /// 0 = the model's (visual/quality: 28 and 16). llvmpipe pays per triangle drawn, and the
  /// robot is mostly cylinders: a chase view needs far fewer than a wrist camera's labels.
  int primitive_slices = 0;
  int primitive_stacks = 0;
};

/// Renders frames of a Simulator's scene. It owns an OSMesa context and a MuJoCo render
/// context; use one Renderer per thread. Draws from different threads are serialised by a
/// process-wide lock (OSMesa is not safe to draw from two threads at once).
class Renderer {
 public:
  Renderer(Simulator& sim, const CameraIntrinsics& intrinsics, const RenderOptions& options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Frame from the wrist camera at the simulator's current state (robot visible).
  LabelledFrame render_wrist_camera();
  /// Draws the wrist camera's passes once and discards them: the software rasteriser compiles
  /// its shaders on first use (~0.3 s), which a caller can so move off its first frame (e.g.
  /// onto another thread during set-up). Reads the simulator's state, changes no image after.
  void warm_up();
  /// Frame from a free-floating camera at T_world_camera, robot hidden.
  LabelledFrame render_free_camera(const Pose& T_world_camera);
  /// Any camera pose; `show_robot` chooses whether robot geoms are drawn; `labels` adds the
  /// segmentation pass.
  LabelledFrame render(const Pose& T_world_camera, bool show_robot, bool labels = true);
  /// The planar depth [m] alone (0 = nothing in the camera's valid range) of the world without
  /// the robot: render(T, false, false).depth_m bit for bit, cheaper (a truth render, e.g. the
  /// oracle's). Drawn unlit (lights change only colours; the depth test and values are the same)
  /// and only the depth read back.
  Image<float> render_depth(const Pose& T_world_camera);
  /// RGB only, with `caption` drawn in the top-left corner (MuJoCo's overlay font), for videos.
  Image<Rgb8> render_captioned(const Pose& T_world_camera, bool show_robot, const std::string& caption);
  /// A video frame (RGB with `caption`, robot shown) that looks as render_captioned's, made
  /// cheaper for a camera that stands still: while `T_world_camera` repeats, the world without
  /// the robot is drawn once and kept (RGB and depth), the caption is drawn over the kept world
  /// when it changes, and each frame draws only the robot, in the screen rectangle its geoms'
  /// bounding spheres project to, keeping its pixels where it is nearer than the world. A frame
  /// whose robot geoms, caption and camera all repeat is the last frame again, drawn not at all.
  /// Assumes, as in canopy's scenes, that only the robot moves and that shadows are off (the
  /// robot casts none on the kept world).
  Image<Rgb8> render_video_frame(const Pose& T_world_camera, const std::string& caption);
  /// How the last render_video_frame was made.
  using VideoPath = sim::VideoPath;
  VideoPath last_video_path() const { return video_.last_path(); }
  /// Pixels of the robot's screen rectangle in the last robot-only frame (0 when it was out of view).
  long last_robot_rect_pixels() const { return video_.robot_rect_pixels(); }
  /// Triangles drawn in the last frame (meshes exactly, primitives as tessellated).
  long last_triangle_count() const { return last_triangles_; }
  /// Geoms drawn in the last frame, and geoms of the scene before culling.
  int last_drawn_geom_count() const { return drawn_geoms_; }
  int last_scene_geom_count() const { return scene_geoms_; }
  /// The depth noise's random state. A caller that discards a frame puts the state from before
  /// it back, and the next frame is noised as if the discarded one had never been drawn.
  Rng noise_state() const { return noise_rng_; }
  void set_noise_state(const Rng& state) { noise_rng_ = state; }
  /// Frustum culling (on by default): geoms that cannot change a pixel are not drawn (outside
  /// the view volume and, with shadows, casting no shadow into it). Images are the same
  /// with it off; the switch exists to compare.
  void set_culling(bool on) { culling_ = on; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }

 private:
  /// The segmentation pass of the scene the last pass() made, read back into the GL buffers
  /// (geom ids as colours). The caller holds the GL lock.
  void label_pass();
  /// Draws the simulator's current (already updated) kinematic state.
  /// `depth` false: RGB only (no depth read back or decoded; the frame's other images are empty).
  LabelledFrame draw(const Pose& T_world_camera, bool show_robot, bool labels, const std::string& caption = "",
                     bool depth = true);

  /// One RGB pass (the world's and/or the robot's geoms, caption) read back into the GL
  /// buffers, raw depth too when `depth`. With `rect` ({left, bottom, width, height}, OpenGL
  /// rows) only that part of the frame is drawn and read back (an off-centre frustum), into
  /// the buffers' first width x height values. The caller holds the GL lock.
  /// `depth_only`: drawn without lights and only the depth read back (the RGB buffer is not).
  void pass(const Pose& T_world_camera, bool world, bool show_robot, const std::string& caption, bool depth,
            const std::array<int, 4>* rect = nullptr, bool depth_only = false);
  /// The planar depth [m] of the raw depth buffer read back last (rows top-down), noised as
  /// the camera says (one draw per valid pixel, row by row); 0 outside the valid range.
  /// `near_m`, `far_m`: the clip planes of the model drawn (taken under the GL lock).
  Image<float> decode_depth(double near_m, double far_m);
  /// The robot's part of the still-camera video frame (render_video_frame); GL lock held.
  void robot_over_kept_world(const Pose& T_world_camera, const std::string& caption);

  /// (Re)makes the MuJoCo scene and render context of the simulator's rendered model (its
  /// meshes uploaded); the caller holds the GL lock with the context current.
  void make_model_context();
  /// After the simulator rebuilt its rendered model (Simulator::show_plants_near): the
  /// context made again; the caller holds the GL lock with the context current.
  void follow_model();

  struct Impl;
  std::unique_ptr<Impl> impl_;
  int generation_ = -1;  // the simulator's render_generation() the context was made for
  Simulator& sim_;
  CameraIntrinsics intrinsics_;
  RenderOptions options_;
  Rng noise_rng_;
  long last_triangles_ = 0;
  int drawn_geoms_ = 0, scene_geoms_ = 0;
  int slices_ = 0, stacks_ = 0;  // the render context's tessellation of primitives
  bool culling_ = true;
  VideoFrameCache video_;  ///< the still-camera video frame: kept world, caption, robot rectangle
};

}  // namespace canopy::sim
