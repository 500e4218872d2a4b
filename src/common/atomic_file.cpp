#include "canopy/common/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "canopy/common/error.h"

namespace fs = std::filesystem;

namespace canopy {

std::string unique_temp_path(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

std::string describe_filesystem_error(const std::filesystem::filesystem_error& e) {
  std::string what = e.code().message();
  if (!e.path1().empty()) what = "'" + e.path1().string() + "': " + what;
  return "cannot write " + what;
}

void move_path(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec) throw IoError("cannot move " + from + " to " + to + ": " + ec.message());
}

void move_temp_into_place(const std::string& tmp, const std::string& path) {
  try {
    move_path(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = unique_temp_path(path);
  // open/write/fsync-free close with errno kept: "No space left on device" is worth saying.
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (fd < 0) throw IoError("cannot write " + path + ": " + std::strerror(errno));
  const char* p = content.data();
  std::size_t left = content.size();
  int err = 0;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      err = n < 0 ? errno : ENOSPC;
      break;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0 && err == 0 && errno != EINTR) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    throw IoError("cannot write " + path + ": " + std::strerror(err));
  }
  move_temp_into_place(tmp, path);
}

void write_json_atomic(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

bool remove_tree(const std::string& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
  if (!ec) return true;
  // A read-only folder (a result the user protected, a umask that took the write bit) keeps
  // its entries: give the owner write and search permission on every folder, then retry.
  for (auto it = fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code ec2;
    if (it->is_directory(ec2) && !it->is_symlink(ec2))
      fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ec2);
  }
  std::error_code ec2;
  if (fs::is_directory(fs::symlink_status(path, ec2)))
    fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec2);
  ec.clear();
  fs::remove_all(path, ec);
  if (ec) {  // permissions of the folder inside may have hidden deeper ones: one more pass
    for (auto it = fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec2);
         !ec2 && it != fs::recursive_directory_iterator(); it.increment(ec2)) {
      std::error_code ec3;
      if (it->is_directory(ec3) && !it->is_symlink(ec3))
        fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ec3);
    }
    ec.clear();
    fs::remove_all(path, ec);
  }
  return !ec;
}

}  // namespace canopy
