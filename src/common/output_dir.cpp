#include "canopy/common/output_dir.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"

namespace fs = std::filesystem;

namespace canopy {

namespace {
std::string strip_slashes(std::string dir) {
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  return dir;
}
bool has_marker(const std::string& dir) {
  std::error_code ec;
  return fs::exists(fs::path(dir) / kOutputMarker, ec);
}
void create_dir(const std::string& dir, const std::string& option) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(option + ": cannot create folder '" + dir + "': " + ec.message());
}
bool is_symlink(const std::string& path) {
  std::error_code ec;
  return fs::is_symlink(fs::symlink_status(path, ec));
}
bool exists_here(const std::string& path) {  // the entry itself, a dangling symlink too
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}
// An absolute, normal form of `path` with the symlinks of its existing part resolved.
fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) p = fs::absolute(path, ec).lexically_normal();
  return p;
}
bool inside_or_same(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}
}  // namespace

void fault_point(const char* name) {
  // Compiled in and harmless: only a test sets CANOPY_FAULT, to kill the process at a chosen
  // point and check that the next run recovers.
  const char* f = std::getenv("CANOPY_FAULT");
  if (f && std::strcmp(f, name) == 0) std::raise(SIGKILL);
}

std::string output_kind(const std::string& dir) {
  std::error_code ec;
  const fs::path marker = fs::path(dir) / kOutputMarker;
  if (!fs::exists(marker, ec)) return "";
  std::ifstream in(marker);
  std::string first;
  std::getline(in, first);
  if (first.rfind("canopy ", 0) == 0 && first.size() > 7) return first.substr(7);
  return "any";  // an older marker: "written by canopy; a later run may replace this folder"
}

void write_output_marker(const std::string& dir, const std::string& kind) {
  write_file_atomic(dir + "/" + kOutputMarker,
                    "canopy " + kind + "\nwritten by `canopy " + kind + "`; only output of the same kind replaces it\n");
}

// ---- LockFile --------------------------------------------------------------------------------

LockFile::~LockFile() { release(); }

bool LockFile::try_lock(const std::string& path, const std::string& what) {
  release();
  for (int attempt = 0; attempt < 10; ++attempt) {
    // O_NOFOLLOW: a planted symlink never makes canopy create or open a file elsewhere;
    // O_NONBLOCK: a FIFO planted in its place does not hang the open.
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd < 0) {
      if (errno == ELOOP || is_symlink(path))
        throw InputError(what + ": the lock file '" + path + "' is a symbolic link; canopy's lock files are plain "
                         "files (remove it)");
      throw IoError(what + ": cannot create the lock file '" + path + "': " + std::strerror(errno));
    }
    struct stat locked;
    if (::fstat(fd, &locked) != 0 || !S_ISREG(locked.st_mode)) {
      ::close(fd);
      throw InputError(what + ": the lock file '" + path + "' is not a plain file (remove it)");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd);
      return false;
    }
    // The holder before us may have removed the file after we opened it: lock the file that
    // is at the path now.
    struct stat at_path;
    if (::lstat(path.c_str(), &at_path) == 0 && at_path.st_ino == locked.st_ino && at_path.st_dev == locked.st_dev) {
      fd_ = fd;
      path_ = path;
      return true;
    }
    ::close(fd);
  }
  throw IoError(what + ": cannot lock '" + path + "'");
}

void LockFile::release() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
  path_.clear();
}

// ---- Checks ----------------------------------------------------------------------------------

void StagedDir::check_writable(const std::string& dir, const std::string& kind, const std::string& option) {
  std::error_code ec;
  if (is_symlink(dir)) {
    const fs::path target = fs::read_symlink(dir, ec);
    if (!fs::exists(dir, ec))
      throw InputError(option + ": '" + dir + "' is a symbolic link to '" + target.string() +
                       "', which does not exist; give a folder, not a link");
    throw InputError(option + ": '" + dir + "' is a symbolic link (to '" + target.string() +
                     "'); give the folder itself (canopy replaces output folders by renames)");
  }
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) throw InputError(option + ": '" + dir + "' exists and is not a folder");
  if (fs::is_empty(dir, ec)) return;
  const std::string found = output_kind(dir);
  if (found.empty())
    throw InputError(option + ": folder '" + dir +
                     "' is not empty and was not written by canopy; choose another folder (canopy never "
                     "replaces or adds to it)");
  if (found != kind && found != "any")
    throw InputError(option + ": folder '" + dir + "' holds the output of `canopy " + found + "`, not of `canopy " + kind +
                     "`; choose another folder (canopy replaces a folder only with output of the same kind)");
}

void check_output_place(const std::string& path, const std::string& option) {
  const std::string p = strip_slashes(path);
  if (p.empty()) throw InputError(option + ": the output name is empty");
  // Inside another canopy output: a later run of that command replaces its folder as a whole,
  // and this output with it. (Experiment folders collect their trials' missions by design and
  // are never replaced as a whole.)
  const fs::path abs = resolved(p);
  for (fs::path d = abs.parent_path(); !d.empty(); d = d.parent_path()) {
    const std::string kind = output_kind(d.string());
    if (!kind.empty() && kind != "experiment")
      throw InputError(option + ": '" + path + "' is inside '" + d.string() + "', the output of `canopy " + kind +
                       "`, which a later run replaces as a whole; write it elsewhere");
    if (d == d.root_path()) break;
  }
}

void check_disjoint_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i)
    for (std::size_t j = 0; j < outputs.size(); ++j) {
      if (i == j || outputs[i].first.empty() || outputs[j].first.empty()) continue;
      const fs::path a = resolved(strip_slashes(outputs[i].first));
      const fs::path b = resolved(strip_slashes(outputs[j].first));
      if (a == b)
        throw InputError(outputs[i].second + " and " + outputs[j].second + " name the same place '" + outputs[i].first +
                         "'; give each its own");
      if (inside_or_same(a, b) || inside_or_same(a, fs::path(b.string() + ".partial")))
        throw InputError(outputs[i].second + ": '" + outputs[i].first + "' is inside " + outputs[j].second + " '" +
                         outputs[j].first + "', which the run replaces as a whole; write it elsewhere");
    }
}

// A commit killed between its renames leaves <dir> absent, the earlier output in
// <dir>.old.tmpN and the new, complete one in <dir>.partial (commit() is reached only with
// complete output): finish the swap. With <dir> present, a leftover <dir>.old.tmpN is an
// earlier output whose removal did not finish.
void StagedDir::finish_interrupted_commit() {
  const fs::path final_path(final_dir_);
  const fs::path parent = final_path.has_parent_path() ? final_path.parent_path() : fs::path(".");
  const std::string prefix = final_path.filename().string() + ".old.tmp";
  std::error_code ec;
  std::vector<fs::path> olds;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().rfind(prefix, 0) == 0) olds.push_back(it->path());
  if (olds.empty()) return;
  const std::string staging = final_dir_ + ".partial";
  for (const fs::path& old : olds) {
    if (!exists_here(final_dir_)) {
      if (exists_here(staging) && has_marker(staging)) move_path(staging, final_dir_);  // finish the swap
      else move_path(old.string(), final_dir_);  // put the earlier output back
      if (!exists_here(old.string())) continue;
    }
    remove_tree(old.string());
  }
}

// ---- StagedDir -------------------------------------------------------------------------------

StagedDir::StagedDir(std::string final_dir, std::string kind, Mode mode, std::string option)
    : final_dir_(strip_slashes(std::move(final_dir))), option_(std::move(option)), kind_(std::move(kind)) {
  if (final_dir_.empty()) throw InputError(option_ + ": the output folder name is empty");
  const std::string staging = final_dir_ + ".partial";
  check_output_place(final_dir_, option_);
  check_writable(final_dir_, kind_, option_);
  check_writable(staging, kind_, option_);
  {
    std::error_code ec;
    const fs::path parent = fs::absolute(final_dir_, ec).parent_path();
    if (!fs::is_directory(parent, ec)) create_dir(parent.string(), option_);
  }
  if (!lock_.try_lock(final_dir_ + ".lock", option_))
    throw InputError(option_ + ": folder '" + final_dir_ +
                     "' is busy: another canopy command is writing it now (try again when it has finished)");
  try {
    finish_interrupted_commit();
    check_writable(final_dir_, kind_, option_);  // again: the swap may have changed it
    std::error_code ec;
    if (mode == Mode::kResume && fs::exists(final_dir_, ec)) {
      working_dir_ = final_dir_;
    } else if (mode == Mode::kResume && fs::exists(staging, ec)) {
      working_dir_ = staging;  // an interrupted run
    } else {
      working_dir_ = staging;
      if (exists_here(staging) && !remove_tree(staging))
        throw IoError(option_ + ": cannot remove the unfinished '" + staging + "' an earlier run left");
      created_ = true;
      create_dir(staging, option_);
    }
    if (!has_marker(working_dir_)) write_output_marker(working_dir_, kind_);
  } catch (...) {
    if (created_) remove_tree(working_dir_);
    lock_.release();
    throw;
  }
}

StagedDir::~StagedDir() {
  if (!committed_ && created_ && !keep_) remove_tree(working_dir_);
  lock_.release();
}

std::string StagedDir::path(const std::string& name) const { return working_dir_ + "/" + name; }

std::string StagedDir::make_subdir(const std::string& name) const {
  const std::string dir = path(name);
  create_dir(dir, option_);
  return dir;
}

void StagedDir::commit() {
  if (working_dir_ == final_dir_) {
    committed_ = true;
    lock_.release();
    return;
  }
  // Move the previous output aside, move the new one in, then delete the old one: <dir>
  // never holds a mix of both. A kill between the renames is finished by the next run
  // (finish_interrupted_commit).
  const std::string old = unique_temp_path(final_dir_ + ".old");
  const bool had_previous = exists_here(final_dir_);
  if (had_previous) move_path(final_dir_, old);
  fault_point("after_first_rename");
  try {
    move_path(working_dir_, final_dir_);
  } catch (...) {
    std::error_code ec;
    if (had_previous) fs::rename(old, final_dir_, ec);
    throw;
  }
  committed_ = true;
  if (had_previous) remove_tree(old);  // what stays is removed by the next run
  lock_.release();
}

}  // namespace canopy
