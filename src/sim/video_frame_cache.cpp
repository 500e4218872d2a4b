#include "canopy/sim/video_frame_cache.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace canopy::sim {

ScreenRect geoms_screen_rect(const mjvScene& scene, const Pose& T_world_camera, double f_px, int W, int H,
                             double near_m) {
  const ScreenRect whole{0, 0, W, H};
  const Pose T_camera_world = T_world_camera.inverse();
  double u0 = std::numeric_limits<double>::infinity(), v0 = u0, u1 = -u0, v1 = -u0;
  for (int i = 0; i < scene.ngeom; ++i) {
    const mjvGeom& g = scene.geoms[i];
    if (!(g.modelrbound > 0.f)) return whole;
    const Vec3 c = T_camera_world * Vec3(g.pos[0], g.pos[1], g.pos[2]);
    const double rad = g.modelrbound * (1.0 + 1e-4) + 1e-3;  // float positions
    if (c.z() - rad <= near_m) return whole;
    // x / z over the sphere's bounding box [x - r, x + r] x [z - r, z + r] is extreme at a corner.
    for (const double dz : {-rad, rad})
      for (const double d : {-rad, rad}) {
        const double z = c.z() + dz;
        u0 = std::min(u0, f_px * (c.x() + d) / z);
        u1 = std::max(u1, f_px * (c.x() + d) / z);
        v0 = std::min(v0, f_px * (c.y() + d) / z);
        v1 = std::max(v1, f_px * (c.y() + d) / z);
      }
  }
  if (!(u0 <= u1)) return {0, 0, 0, 0};
  // Image column u = x / z * f + W / 2; OpenGL row = H / 2 - y / z * f (image rows grow downwards).
  const int left = std::max(0, static_cast<int>(std::floor(u0 + 0.5 * W)) - 2);
  const int right = std::min(W, static_cast<int>(std::ceil(u1 + 0.5 * W)) + 2);
  const int bottom = std::max(0, static_cast<int>(std::floor(0.5 * H - v1)) - 2);
  const int top = std::min(H, static_cast<int>(std::ceil(0.5 * H - v0)) + 2);
  if (left >= right || bottom >= top) return {0, 0, 0, 0};
  return {left, bottom, right - left, top - bottom};
}

bool rects_overlap(const ScreenRect& a, const ScreenRect& b) {
  return a[2] > 0 && a[3] > 0 && b[2] > 0 && b[3] > 0 && a[0] < b[0] + b[2] && b[0] < a[0] + a[2] &&
         a[1] < b[1] + b[3] && b[1] < a[1] + a[3];
}

namespace {
// Copies the rectangle `rect` of full-frame RGB rows (width W) from `from` into `to`.
void copy_rect(const std::vector<unsigned char>& from, std::vector<unsigned char>* to, const ScreenRect& rect,
               int W) {
  for (int y = rect[1]; y < rect[1] + rect[3]; ++y) {
    const std::size_t at = 3 * (static_cast<std::size_t>(y) * W + rect[0]);
    std::memcpy(to->data() + at, from.data() + at, 3 * static_cast<std::size_t>(rect[2]));
  }
}
}  // namespace

bool VideoFrameCache::camera_still(const Pose& T_world_camera, bool shadows) {
  const bool still = !shadows && T_world_camera.matrix() == T_.matrix();
  T_ = T_world_camera;
  return still;
}

void VideoFrameCache::full_frame() {
  has_world_ = false;
  path_ = VideoPath::kFull;
}

void VideoFrameCache::keep_world(const std::vector<unsigned char>& rgb, const std::vector<float>& depth) {
  world_rgb_ = rgb;
  world_depth_ = depth;
  has_world_ = true;
  captioned_ = false;
}

bool VideoFrameCache::needs_caption(const std::string& caption) const { return !captioned_ || caption != caption_; }

void VideoFrameCache::set_captioned_world(std::vector<unsigned char> captioned_rgb, const std::string& caption) {
  const int W = width_, H = height_;
  captioned_rgb_ = std::move(captioned_rgb);
  caption_box_ = {0, 0, 0, 0};
  if (!caption.empty()) {
    // Where the caption changed the world, padded by 4 pixels (a backdrop may leave a pixel
    // unchanged): a robot rectangle reaching it draws the caption too.
    int x0 = W, y0 = H, x1 = -1, y1 = -1;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const std::size_t s = 3 * (static_cast<std::size_t>(y) * W + x);
        if (std::memcmp(&captioned_rgb_[s], &world_rgb_[s], 3) != 0) {
          x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
      }
    if (x1 >= 0) {
      x0 = std::max(0, x0 - 4), y0 = std::max(0, y0 - 4), x1 = std::min(W - 1, x1 + 4), y1 = std::min(H - 1, y1 + 4);
      caption_box_ = {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
    }
  }
  frame_rgb_ = captioned_rgb_;
  rect_ = {0, 0, 0, 0};
  captioned_ = true;
}

bool VideoFrameCache::robot_changed(const mjvScene& robot_scene, bool redraw) {
  // The robot's geoms where they are now; the same as in the last frame: the same frame.
  std::vector<float> robot;
  robot.reserve(13 * static_cast<std::size_t>(robot_scene.ngeom));
  for (int i = 0; i < robot_scene.ngeom; ++i) {
    const mjvGeom& g = robot_scene.geoms[i];
    robot.insert(robot.end(), g.pos, g.pos + 3);
    robot.insert(robot.end(), g.mat, g.mat + 9);
    robot.push_back(static_cast<float>(g.objid));
  }
  if (!redraw && robot == robot_) {
    path_ = VideoPath::kReused;
    return false;
  }
  robot_ = std::move(robot);
  path_ = VideoPath::kRobotOnly;
  return true;
}

ScreenRect VideoFrameCache::start_robot(const mjvScene& robot_scene, const Pose& T_world_camera, double f_px,
                                        double near_m) {
  const ScreenRect rect = geoms_screen_rect(robot_scene, T_world_camera, f_px, width_, height_, near_m);
  copy_rect(captioned_rgb_, &frame_rgb_, rect_, width_);  // the last frame's robot away
  rect_ = rect;
  robot_rect_pixels_ = static_cast<long>(rect[2]) * rect[3];
  return rect;
}

void VideoFrameCache::compose_robot(const std::vector<unsigned char>& robot_rgb,
                                    const std::vector<float>& robot_depth) {
  const ScreenRect& rect = rect_;
  const int W = width_;
  // The robot where it is nearer than the world (the caption, drawn over both, is in both).
  for (int j = 0; j < rect[3]; ++j)
    for (int i = 0; i < rect[2]; ++i) {
      const std::size_t s = static_cast<std::size_t>(j) * rect[2] + i;
      const std::size_t f = static_cast<std::size_t>(rect[1] + j) * W + rect[0] + i;
      const unsigned char* from = robot_depth[s] < world_depth_[f] ? &robot_rgb[3 * s] : &captioned_rgb_[3 * f];
      std::memcpy(&frame_rgb_[3 * f], from, 3);
    }
}

}  // namespace canopy::sim
