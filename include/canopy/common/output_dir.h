#pragma once
// Output folders: the marker naming the kind of output, and StagedDir, which every command
// writes its folder through (checked, locked, staged and committed by renames).

#include <string>
#include <utility>
#include <vector>

namespace canopy {

/// Name of the marker file canopy puts in every output folder it writes. Its first line is
/// "canopy <kind>": the kind of output (the command that wrote it: world, render, mission,
/// map, ablate, experiment, report, reach, plant, ...).
constexpr const char* kOutputMarker = ".canopy-output";

/// The kind a folder's marker names: "" when the folder has no marker, "any" for a marker of
/// an older canopy that named no kind.
std::string output_kind(const std::string& dir);
/// Writes the marker of `kind` into `dir`.
void write_output_marker(const std::string& dir, const std::string& kind);

/// An advisory lock (flock) on a plain file, held while the object lives; released (and the
/// file removed) by release() or the destructor, and by the system when the process dies.
class LockFile {
 public:
  LockFile() = default;
  ~LockFile();
  LockFile(const LockFile&) = delete;
  LockFile& operator=(const LockFile&) = delete;
  /// Takes the lock on `path` (created when absent): false when another process holds it.
  /// Never follows a symbolic link: a link at `path` (or a FIFO, a folder) is InputError; a
  /// lock file that cannot be created is IoError. `what` names the option in errors.
  bool try_lock(const std::string& path, const std::string& what);
  void release();
  bool held() const { return fd_ >= 0; }
  int fd() const { return fd_; }  ///< The open lock file (a child that inherits it holds the lock too).

 private:
  std::string path_;
  int fd_ = -1;
};

/// Throws InputError (naming `option`) when an output at `path` would lie inside another
/// command's output folder (a folder with a marker of a kind other than "experiment"), which
/// a later run of that command replaces as a whole, or when its name is empty.
void check_output_place(const std::string& path, const std::string& option);
/// Throws InputError when one of a command's outputs (path, option name) is the same place as
/// another or lies inside another (or its `.partial`): `--export o/ds` with `--out o` would be
/// lost when `o` is committed. Empty paths are skipped.
void check_disjoint_outputs(const std::vector<std::pair<std::string, std::string>>& outputs);

/// Fault injection for tests: kills the process (SIGKILL) when the environment variable
/// CANOPY_FAULT equals `name` (e.g. "after_first_rename", between the two renames of a commit).
void fault_point(const char* name);

/// A command's output folder, guarded the same way by every command (world, render, run,
/// map, reach, ablate, mission, report, import-plant):
///  - canopy marks each folder it writes with kOutputMarker, naming the kind of output, and
///    never replaces or adds to a non-empty folder without it (InputError: the folder is the
///    user's), nor one holding another kind of output (an experiment is never replaced by a
///    report, a mission never turned into an experiment);
///  - the folder itself is never a symbolic link (dangling or not) and never lies inside
///    another command's output folder; both are refused before any work;
///  - one command at a time: a second command writing the same folder is refused while the
///    first runs (an advisory lock on `<dir>.lock`, released when the first ends, also by a
///    crash);
///  - Mode::kReplace (the default): files go to `<dir>.partial`; commit() swaps it in for
///    `<dir>` by renames, so `<dir>` holds either the previous complete output or the new one;
///    a commit killed between its renames is finished by the next command on `<dir>`;
///  - Mode::kResume (--resume): files go into the existing canopy folder `<dir>` itself, or
///    into the `<dir>.partial` an interrupted run left (renamed to `<dir>` by commit()), or,
///    when neither exists, into a new `<dir>.partial`.
/// Write every file with write_file_atomic (or the write_*_atomic helpers), so an
/// interrupted run leaves only whole files. A folder this object created is removed when
/// commit() is not reached (the command failed); an existing folder being resumed is kept.
/// When the folder cannot be set up (disk full, read-only), nothing is left: no `.partial`,
/// no `.lock`.
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
  void finish_interrupted_commit();
  std::string final_dir_;
  std::string working_dir_;
  std::string option_;
  std::string kind_;
  LockFile lock_;
  bool created_ = false;  ///< working_dir_ was made by this object
  bool committed_ = false;
  bool keep_ = false;
};

}  // namespace canopy
