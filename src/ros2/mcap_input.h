#pragma once
// How the MCAP reader takes bytes from its file: a regular file read with pread (a read past
// its end is InputError: the file was cut short) and a read-ahead window for the many small
// reads of a scan (record prefixes, message headers). Internal to the ros2 module.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace canopy::ros2::reader_detail {

/// The read-ahead of a Window: one read serves the prefixes of many small records.
constexpr std::size_t kReadAheadBytes = std::size_t(1) << 20;

/// A regular file read with pread; a read past its end is InputError (the file is cut short).
class File {
 public:
  /// Opens `path`; InputError when it is missing, a folder or not a regular file (a FIFO does
  /// not hang the open), IoError when the system refuses it.
  explicit File(const std::string& path);
  ~File();
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  std::uint64_t size() const { return size_; }
  /// Reads `n` bytes at `offset` into `out`.
  void read(std::uint64_t offset, std::size_t n, char* out) const;
  /// `n` bytes at `offset`.
  std::string read(std::uint64_t offset, std::size_t n) const {
    std::string s(n, '\0');
    read(offset, n, s.data());
    return s;
  }

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// Small reads through a read-ahead buffer (record prefixes and message headers of a scan).
class Window {
 public:
  /// Reads of `file` that end at or before `end`.
  Window(const File& file, std::uint64_t end) : file_(file), end_(end) {}
  /// `n` bytes at `offset` (valid until the next get); callers check offset + n <= end.
  std::string_view get(std::uint64_t offset, std::size_t n) {
    if (offset < base_ || offset + n > base_ + buf_.size()) {
      const std::uint64_t avail = end_ - offset;  // callers check offset + n <= end
      buf_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(avail, std::max(n, kReadAheadBytes))));
      file_.read(offset, buf_.size(), buf_.data());
      base_ = offset;
    }
    return std::string_view(buf_).substr(static_cast<std::size_t>(offset - base_), n);
  }

 private:
  const File& file_;
  std::uint64_t end_;
  std::uint64_t base_ = 0;
  std::string buf_;
};

}  // namespace canopy::ros2::reader_detail
