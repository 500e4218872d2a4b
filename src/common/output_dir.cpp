#include "canopy/common/output_dir.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
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
  if (ec) throw InputError(option + ": cannot create folder '" + dir + "': " + ec.message());
}
}  // namespace

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

void StagedDir::check_writable(const std::string& dir, const std::string& kind, const std::string& option) {
  std::error_code ec;
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

namespace {
// An advisory lock on `<dir>.lock` for the life of the StagedDir; -1 when the folder is busy.
int lock_output(const std::string& lock_path, const std::string& option, const std::string& dir) {
  for (int attempt = 0; attempt < 10; ++attempt) {
    const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw InputError(option + ": cannot create the lock file '" + lock_path + "': " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd);
      throw InputError(option + ": folder '" + dir +
                       "' is busy: another canopy command is writing it now (try again when it has finished)");
    }
    // The holder before us may have removed the file after we opened it: lock the file that
    // is at the path now.
    struct stat at_path, locked;
    if (::stat(lock_path.c_str(), &at_path) == 0 && ::fstat(fd, &locked) == 0 && at_path.st_ino == locked.st_ino &&
        at_path.st_dev == locked.st_dev)
      return fd;
    ::close(fd);
  }
  throw InputError(option + ": cannot lock '" + lock_path + "'");
}
}  // namespace

StagedDir::StagedDir(std::string final_dir, std::string kind, Mode mode, std::string option)
    : final_dir_(strip_slashes(std::move(final_dir))), option_(std::move(option)), kind_(std::move(kind)) {
  if (final_dir_.empty()) throw InputError(option_ + ": the output folder name is empty");
  const std::string staging = final_dir_ + ".partial";
  check_writable(final_dir_, kind_, option_);
  check_writable(staging, kind_, option_);
  {
    std::error_code ec;
    const fs::path parent = fs::absolute(final_dir_, ec).parent_path();
    if (!fs::is_directory(parent, ec)) create_dir(parent.string(), option_);
  }
  lock_fd_ = lock_output(final_dir_ + ".lock", option_, final_dir_);
  std::error_code ec;
  if (mode == Mode::kResume && fs::exists(final_dir_, ec)) {
    working_dir_ = final_dir_;
  } else if (mode == Mode::kResume && fs::exists(staging, ec)) {
    working_dir_ = staging;  // an interrupted run
  } else {
    working_dir_ = staging;
    fs::remove_all(staging, ec);
    create_dir(staging, option_);
    created_ = true;
  }
  if (!has_marker(working_dir_)) write_output_marker(working_dir_, kind_);
}

StagedDir::~StagedDir() {
  if (!committed_ && created_ && !keep_) {
    std::error_code ec;
    fs::remove_all(working_dir_, ec);
  }
  unlock();
}

void StagedDir::unlock() {
  if (lock_fd_ < 0) return;
  ::unlink((final_dir_ + ".lock").c_str());
  ::close(lock_fd_);
  lock_fd_ = -1;
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
    unlock();
    return;
  }
  // Move the previous output aside, move the new one in, then delete the old one: <dir>
  // never holds a mix of both.
  std::error_code ec;
  const std::string old = unique_temp_path(final_dir_ + ".old");
  const bool had_previous = fs::exists(final_dir_, ec);
  if (had_previous) move_path(final_dir_, old);
  try {
    move_path(working_dir_, final_dir_);
  } catch (...) {
    if (had_previous) fs::rename(old, final_dir_, ec);
    throw;
  }
  committed_ = true;
  if (had_previous) fs::remove_all(old, ec);
  unlock();
}

}  // namespace canopy
