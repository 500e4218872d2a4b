#pragma once
// File output: atomic writes, PNG images, JSON, and parsing of command-line vectors.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "canopy/common/image.h"
#include "canopy/common/types.h"

namespace canopy {

/// Writes `content` to `path` atomically (temporary file in the same folder, then rename).
void write_file_atomic(const std::string& path, const std::string& content);
/// Writes pretty-printed JSON atomically.
void write_json_atomic(const std::string& path, const nlohmann::json& j);
/// Largest file read_file reads whole by default (maps, meshes, CSV ground truth).
constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t(1) << 30;
/// Reads a whole file; throws InputError when it is a folder, not a regular file (a device
/// such as /dev/zero, a pipe), larger than `max_bytes`, or cannot be opened or read.
std::string read_file(const std::string& path, std::uintmax_t max_bytes = kMaxInputFileBytes);

/// A number as text for CSV and report files, by a printf format for one double
/// ("%.9g" keeps a float's value; "%.17g" a double's).
std::string format_number(double x, const char* printf_format = "%.9g");

/// Largest image the PNG readers accept (a header claiming more is an error, read before any
/// pixel memory is allocated).
constexpr std::uint32_t kMaxImageSidePx = 16384;
constexpr std::uint64_t kMaxImagePixels = std::uint64_t(64) << 20;

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
/// Parses a whole number in [0, max] written in decimal digits only (no sign, no wrap-around:
/// "-1" and "99999999999999999999" are errors naming `what`).
std::uint64_t parse_uint64(const std::string& text, const std::string& what,
                           std::uint64_t max = std::numeric_limits<std::uint64_t>::max());
/// Parses "x,y,z,qw,qx,qy,qz"; the quaternion must be unit length within 1e-3.
Pose parse_pose7(const std::string& text, const std::string& what);
/// Parses "x,y,yaw" (metres, radians).
BasePose parse_base_pose(const std::string& text, const std::string& what);

/// JSON of a pose as {"position":[x,y,z],"quaternion_wxyz":[w,x,y,z]}.
nlohmann::json pose_to_json(const Pose& T);
Pose pose_from_json(const nlohmann::json& j);

/// Name of the marker file canopy puts in every output folder it writes. Its first line is
/// "canopy <kind>": the kind of output (the command that wrote it: world, render, mission,
/// map, ablate, experiment, report, reach, plant, ...).
constexpr const char* kOutputMarker = ".canopy-output";

/// The kind a folder's marker names: "" when the folder has no marker, "any" for a marker of
/// an older canopy that named no kind.
std::string output_kind(const std::string& dir);
/// Writes the marker of `kind` into `dir`.
void write_output_marker(const std::string& dir, const std::string& kind);

/// A command's output folder, guarded the same way by every command (world, render, run,
/// map, reach, ablate, mission, report, import-plant):
///  - canopy marks each folder it writes with kOutputMarker, naming the kind of output, and
///    never replaces or adds to a non-empty folder without it (InputError: the folder is the
///    user's), nor one holding another kind of output (an experiment is never replaced by a
///    report, a mission never turned into an experiment);
///  - one command at a time: a second command writing the same folder is refused while the
///    first runs (an advisory lock on `<dir>.lock`, released when the first ends, also by a
///    crash);
///  - Mode::kReplace (the default): files go to `<dir>.partial`; commit() swaps it in for
///    `<dir>` by renames, so `<dir>` holds either the previous complete output or the new one;
///  - Mode::kResume (--resume): files go into the existing canopy folder `<dir>` itself, or
///    into the `<dir>.partial` an interrupted run left (renamed to `<dir>` by commit()), or,
///    when neither exists, into a new `<dir>.partial`.
/// Write every file with write_file_atomic (or the write_*_atomic helpers), so an
/// interrupted run leaves only whole files. A folder this object created is removed when
/// commit() is not reached (the command failed); an existing folder being resumed is kept.
class StagedDir {
 public:
  enum class Mode { kReplace, kResume };
  /// Checks, locks and prepares the folder for output of `kind`; `option` names the flag in
  /// errors. Throws InputError when `final_dir` is a file, a non-empty folder canopy did not
  /// write, a folder of another kind, busy (another command writes it), or cannot be made.
  StagedDir(std::string final_dir, std::string kind, Mode mode = Mode::kReplace, std::string option = "--out");
  ~StagedDir();  ///< Removes a folder it created when commit() was not reached (unless keep()).
  StagedDir(const StagedDir&) = delete;
  StagedDir& operator=(const StagedDir&) = delete;

  /// Throws InputError (naming `option`) unless canopy may write output of `kind` into `dir`:
  /// absent, an empty folder, or a folder whose marker names `kind` (or no kind).
  static void check_writable(const std::string& dir, const std::string& kind, const std::string& option = "--out");

  /// Path of a file inside the working folder ("" gives the folder with a trailing '/').
  std::string path(const std::string& name) const;
  /// Creates a sub-folder (and its parents) of the working folder; returns its path.
  std::string make_subdir(const std::string& name) const;
  /// The folder being written: `<dir>.partial`, or `<dir>` when resuming it in place.
  const std::string& working_dir() const { return working_dir_; }
  const std::string& final_dir() const { return final_dir_; }
  /// True when the working folder existed already (resume mode): its files may be reused.
  bool resuming() const { return !created_; }
  /// Publishes the output as `<dir>` (a no-op when resuming `<dir>` in place).
  void commit();
  /// Leaves the working folder in place when commit() is not reached (an interrupted run that
  /// `--resume` continues).
  void keep() { keep_ = true; }

 private:
  void unlock();
  std::string final_dir_;
  std::string working_dir_;
  std::string option_;
  std::string kind_;
  int lock_fd_ = -1;
  bool created_ = false;  ///< working_dir_ was made by this object
  bool committed_ = false;
  bool keep_ = false;
};

}  // namespace canopy
