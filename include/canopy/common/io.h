#pragma once
// File output: atomic writes, PNG images, JSON, and parsing of command-line vectors.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/image.h"
#include "canopy/common/types.h"

namespace canopy {

/// Writes `content` to `path` atomically (temporary file in the same folder, then rename).
void write_file_atomic(const std::string& path, const std::string& content);
/// Writes pretty-printed JSON atomically.
void write_json_atomic(const std::string& path, const nlohmann::json& j);
/// Reads a whole file; throws InputError when it cannot be opened.
std::string read_file(const std::string& path);

/// PNG writers (atomic). 16-bit images are stored big-endian as PNG requires.
void write_png(const std::string& path, const Image<Rgb8>& image);
void write_png_gray16(const std::string& path, const Image<std::uint16_t>& image);
/// Reads an 8-bit RGB or RGBA PNG (alpha dropped); throws InputError on failure.
Image<Rgb8> read_png_rgb(const std::string& path);
/// Reads a 16-bit grayscale PNG; throws InputError on failure.
Image<std::uint16_t> read_png_gray16(const std::string& path);

/// Parses "a,b,c" into exactly `count` finite numbers (count < 0: any number); throws
/// InputError naming `what` otherwise.
std::vector<double> parse_numbers(const std::string& text, int count, const std::string& what);
/// Parses "x,y,z,qw,qx,qy,qz"; the quaternion must be unit length within 1e-3.
Pose parse_pose7(const std::string& text, const std::string& what);
/// Parses "x,y,yaw" (metres, radians).
BasePose parse_base_pose(const std::string& text, const std::string& what);

/// JSON of a pose as {"position":[x,y,z],"quaternion_wxyz":[w,x,y,z]}.
nlohmann::json pose_to_json(const Pose& T);
Pose pose_from_json(const nlohmann::json& j);

/// Creates a results folder. Output that must not look complete when a run fails is
/// written into `<dir>.partial` and moved to `<dir>` by commit().
class StagedDir {
 public:
  explicit StagedDir(std::string final_dir);
  ~StagedDir();  ///< Removes the staging folder when commit() was not reached.
  StagedDir(const StagedDir&) = delete;
  StagedDir& operator=(const StagedDir&) = delete;
  /// Path of a file inside the staging folder.
  std::string path(const std::string& name) const;
  /// Replaces `<dir>` by the staging folder.
  void commit();

 private:
  std::string final_dir_;
  std::string staging_dir_;
  bool committed_ = false;
};

}  // namespace canopy
