#pragma once
// The still-camera video frame cache behind Renderer::render_video_frame: while the camera
// stands still, the world without the robot is kept (RGB and depth), the caption is drawn over
// it once, and each frame only the robot's screen rectangle is drawn and composited by depth.
// The Renderer draws; this keeps, compares and composes. Images are full-frame, OpenGL rows
// (bottom-up), RGB 3 bytes a pixel.

#include <mujoco/mujoco.h>

#include <array>
#include <string>
#include <vector>

#include "canopy/common/types.h"

namespace canopy::sim {

/// How a video frame was made: the whole scene, the robot over the kept world, or the last
/// frame again.
enum class VideoPath { kFull, kRobotOnly, kReused };

/// A rectangle of pixels {left, bottom, width, height} in OpenGL rows (bottom-up).
using ScreenRect = std::array<int, 4>;

/// The pixels that the scene's geoms may cover, seen from T_world_camera (pinhole fx = fy,
/// principal point at the centre, as the Renderer draws): the bounding box of each geom's
/// bounding sphere's projection, padded by 2 pixels, within the W x H frame. The whole frame
/// when a geom has no bound or reaches the near plane; empty when no geom is in front of the
/// camera and inside the frame.
ScreenRect geoms_screen_rect(const mjvScene& scene, const Pose& T_world_camera, double f_px, int W, int H,
                             double near_m);
/// True when both rectangles are non-empty and share a pixel.
bool rects_overlap(const ScreenRect& a, const ScreenRect& b);

/// What render_video_frame keeps between frames, for a W x H camera.
class VideoFrameCache {
 public:
  VideoFrameCache(int width_px, int height_px) : width_(width_px), height_(height_px) {}

  /// True when this frame may be composed over the kept world: the camera is where it was in
  /// the last video frame and shadows are off (the robot would cast them on the kept world).
  /// Remembers the pose for the next frame.
  bool camera_still(const Pose& T_world_camera, bool shadows);
  /// The frame is drawn whole (the camera moved): the kept world is void.
  void full_frame();
  /// The renderer's buffers were drawn over by another pass: the kept world is void.
  void forget_world() { has_world_ = false; }
  /// True while a kept world is valid.
  bool has_world() const { return has_world_; }
  /// Keeps a full-frame pass of the world without the robot; its caption is still to draw.
  void keep_world(const std::vector<unsigned char>& rgb, const std::vector<float>& depth);
  /// True when the kept world does not yet carry `caption` (the renderer draws it over).
  bool needs_caption(const std::string& caption) const;
  /// The kept world's RGB.
  const std::vector<unsigned char>& world_rgb() const { return world_rgb_; }
  /// Takes the kept world with `caption` drawn over it, finds the box the caption changed
  /// (padded by 4 pixels) and restarts the frame from it, robot not yet drawn.
  void set_captioned_world(std::vector<unsigned char> captioned_rgb, const std::string& caption);
  /// Compares the robot geoms of `robot_scene` (robot only) with the last frame's: false, and
  /// the last frame is reused, when they repeat and nothing was redrawn (`redraw` false).
  bool robot_changed(const mjvScene& robot_scene, bool redraw);
  /// Starts the robot's part: takes the last frame's robot away and returns the rectangle the
  /// robot's geoms now cover (empty when out of view), which the renderer draws the robot in.
  ScreenRect start_robot(const mjvScene& robot_scene, const Pose& T_world_camera, double f_px, double near_m);
  /// True when the robot's rectangle reaches the caption (the robot pass draws it too).
  bool rect_meets_caption(const ScreenRect& rect) const { return rects_overlap(rect, caption_box_); }
  /// Composes the robot pass (RGB and depth of the rectangle only, packed rows) over the
  /// captioned world: the robot where it is nearer than the world.
  void compose_robot(const std::vector<unsigned char>& robot_rgb, const std::vector<float>& robot_depth);
  /// Ends a frame drawn with `caption`.
  void end_frame(const std::string& caption) { caption_ = caption; }

  /// The frame as last composed.
  const std::vector<unsigned char>& frame_rgb() const { return frame_rgb_; }
  /// How the last frame was made.
  VideoPath last_path() const { return path_; }
  /// Pixels of the robot's rectangle in the last robot-only frame.
  long robot_rect_pixels() const { return robot_rect_pixels_; }
  /// The caption's box in the kept world (empty without a caption).
  const ScreenRect& caption_box() const { return caption_box_; }

 private:
  int width_, height_;
  Pose T_ = Pose::Identity();
  std::string caption_;
  bool has_world_ = false;       // the kept world (and frame buffers) are valid
  bool captioned_ = false;       // the kept world carries caption_
  std::vector<float> robot_;     // the robot geoms' poses in the last frame
  ScreenRect rect_{0, 0, 0, 0}, caption_box_{0, 0, 0, 0};
  VideoPath path_ = VideoPath::kFull;
  long robot_rect_pixels_ = 0;
  std::vector<unsigned char> world_rgb_, captioned_rgb_, frame_rgb_;
  std::vector<float> world_depth_;
};

}  // namespace canopy::sim
