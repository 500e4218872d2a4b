#include "canopy/common/io.h"

#include <fcntl.h>
#include <png.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "canopy/common/error.h"

namespace fs = std::filesystem;

namespace canopy {

namespace {

// Unique per process and per call, so concurrent writers never share a temporary file.
std::string temp_name(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

void move_or_throw(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec) throw std::runtime_error("cannot move " + from + " to " + to + ": " + ec.message());
}

// Moves a temporary file into place; removes it when that fails.
void rename_or_throw(const std::string& from, const std::string& to) {
  try {
    move_or_throw(from, to);
  } catch (...) {
    std::error_code ec;
    fs::remove(from, ec);
    throw;
  }
}

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};

// Writes rows through libpng into a temporary file, then renames it into place.
template <typename RowFn>
void write_png_rows(const std::string& path, int width, int height, int bit_depth, int color_type,
                    RowFn&& row_fn) {
  const std::string tmp = temp_name(path);
  std::unique_ptr<FILE, FileCloser> f(std::fopen(tmp.c_str(), "wb"));
  if (!f) throw std::runtime_error("cannot write " + path);
  // Every C++ object lives outside the setjmp/longjmp region: libpng reports errors by
  // longjmp, which must not skip destructors.
  std::vector<png_byte> row;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: out of memory writing " + path);
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    f.reset();
    std::remove(tmp.c_str());
    throw std::runtime_error("libpng: failed writing " + path);
  }
  png_init_io(png, f.get());
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth,
               color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    row_fn(y, row);
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(f.get()) != 0) throw std::runtime_error("cannot write " + path);
  f.reset();
  rename_or_throw(tmp, path);
}

struct PngRead {
  int width = 0, height = 0, bit_depth = 0, color_type = 0, channels = 0;
  std::vector<png_byte> pixels;  // rows packed
  size_t rowbytes = 0;
};

PngRead read_png_raw(const std::string& path) {
  std::unique_ptr<FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f) throw InputError(path + ": cannot open file");
  png_byte sig[8];
  if (std::fread(sig, 1, 8, f.get()) != 8 || png_sig_cmp(sig, 0, 8) != 0)
    throw InputError(path + ": not a PNG file");
  // libpng's own handlers print to stderr; the error becomes this function's one message.
  static thread_local std::string png_message;
  png_message.clear();
  png_structp png = png_create_read_struct(
      PNG_LIBPNG_VER_STRING, nullptr,
      [](png_structp p, png_const_charp msg) {
        png_message = msg ? msg : "";
        png_longjmp(p, 1);
      },
      [](png_structp, png_const_charp) {});
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw std::runtime_error("libpng: out of memory reading " + path);
  }
  PngRead out;
  std::vector<png_bytep> rows;  // declared before setjmp (see write_png_rows)
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw InputError(path + ": corrupt PNG file" + (png_message.empty() ? "" : " (" + png_message + ")"));
  }
  png_init_io(png, f.get());
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  // The header's size is checked before any pixel memory is allocated.
  if (w == 0 || h == 0 || w > kMaxImageSidePx || h > kMaxImageSidePx ||
      std::uint64_t(w) * std::uint64_t(h) > kMaxImagePixels) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw InputError(path + ": the PNG header says " + std::to_string(w) + " x " + std::to_string(h) +
                     " pixels; canopy reads images up to " + std::to_string(kMaxImageSidePx) + " pixels a side and " +
                     std::to_string(kMaxImagePixels) + " pixels in all");
  }
  out.width = static_cast<int>(w);
  out.height = static_cast<int>(h);
  out.bit_depth = png_get_bit_depth(png, info);
  out.color_type = png_get_color_type(png, info);
  if (out.bit_depth == 16) png_set_swap(png);  // host order (little-endian)
  if (out.color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  png_read_update_info(png, info);
  out.channels = png_get_channels(png, info);
  out.rowbytes = png_get_rowbytes(png, info);
  out.pixels.resize(out.rowbytes * static_cast<size_t>(out.height));
  rows.resize(static_cast<size_t>(out.height));
  for (int y = 0; y < out.height; ++y) rows[static_cast<size_t>(y)] = out.pixels.data() + out.rowbytes * y;
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  return out;
}

}  // namespace

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = temp_name(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + path);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write " + path);
    }
  }
  rename_or_throw(tmp, path);
}

void write_json_atomic(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

std::string format_number(double x, const char* printf_format) {
  char b[64];
  std::snprintf(b, sizeof b, printf_format, x);
  return b;
}

std::string read_file(const std::string& path, std::uintmax_t max_bytes) {
  std::error_code ec;
  // A folder opens as an empty stream on Linux: it must not read as an empty file.
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a folder, not a file");
  if (!fs::exists(path, ec)) throw InputError(path + ": cannot open file (it does not exist)");
  // Devices and pipes have no size and may never end (/dev/zero).
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": is not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size (" + ec.message() + ")");
  if (size > max_bytes)
    throw InputError(path + ": is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                     " this input may have");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::string out(static_cast<std::size_t>(size), '\0');
  in.read(out.data(), static_cast<std::streamsize>(size));
  if (in.bad() || in.gcount() != static_cast<std::streamsize>(size)) throw InputError(path + ": cannot read file");
  return out;
}

void write_png(const std::string& path, const Image<Rgb8>& image) {
  write_png_rows(path, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, [&](int y, std::vector<png_byte>& row) {
    row.resize(static_cast<size_t>(image.width) * 3);
    for (int x = 0; x < image.width; ++x) {
      const Rgb8& p = image.at(x, y);
      row[3 * x] = p.r;
      row[3 * x + 1] = p.g;
      row[3 * x + 2] = p.b;
    }
  });
}

void write_png_gray16(const std::string& path, const Image<std::uint16_t>& image) {
  write_png_rows(path, image.width, image.height, 16, PNG_COLOR_TYPE_GRAY, [&](int y, std::vector<png_byte>& row) {
    row.resize(static_cast<size_t>(image.width) * 2);
    for (int x = 0; x < image.width; ++x) {
      const std::uint16_t v = image.at(x, y);
      row[2 * x] = static_cast<png_byte>(v >> 8);
      row[2 * x + 1] = static_cast<png_byte>(v & 0xff);
    }
  });
}

Image<Rgb8> read_png_rgb(const std::string& path) {
  PngRead raw = read_png_raw(path);
  if (raw.bit_depth != 8 || (raw.channels != 3 && raw.channels != 4))
    throw InputError(path + ": expected an 8-bit RGB or RGBA PNG");
  Image<Rgb8> img(raw.width, raw.height);
  for (int y = 0; y < raw.height; ++y)
    for (int x = 0; x < raw.width; ++x) {
      const png_byte* p = raw.pixels.data() + raw.rowbytes * y + raw.channels * x;
      img.at(x, y) = Rgb8{p[0], p[1], p[2]};
    }
  return img;
}

Image<std::uint16_t> read_png_gray16(const std::string& path) {
  PngRead raw = read_png_raw(path);
  if (raw.bit_depth != 16 || raw.channels != 1) throw InputError(path + ": expected a 16-bit grayscale PNG");
  Image<std::uint16_t> img(raw.width, raw.height);
  for (int y = 0; y < raw.height; ++y)
    for (int x = 0; x < raw.width; ++x) {
      const png_byte* p = raw.pixels.data() + raw.rowbytes * y + 2 * x;
      img.at(x, y) = static_cast<std::uint16_t>(p[0] | (p[1] << 8));
    }
  return img;
}

std::vector<double> parse_numbers(const std::string& text, int count, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    // Plain decimal numbers only: stod would also take hexadecimal ("0x10" = 16), "inf" and
    // "nan".
    const std::size_t first = item.find_first_not_of(" \t");
    if (first == std::string::npos || item.find_first_not_of("0123456789+-.eE \t") != std::string::npos)
      throw InputError(what + ": value '" + text + "': '" + item + "' is not a decimal number");
    size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      throw InputError(what + ": value '" + text + "': '" + item + "' is not a number");
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (used != item.size()) throw InputError(what + ": value '" + text + "': '" + item + "' is not a number");
    if (!std::isfinite(v)) throw InputError(what + ": value '" + text + "': '" + item + "' is not finite");
    out.push_back(v);
  }
  if (count >= 0 && static_cast<int>(out.size()) != count)
    throw InputError(what + ": value '" + text + "' must have " + std::to_string(count) +
                     " comma-separated numbers, has " + std::to_string(out.size()));
  return out;
}

std::uint64_t parse_uint64(const std::string& text, const std::string& what, std::uint64_t max) {
  if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != std::string::npos)
    throw InputError(what + ": value '" + text + "' is not a whole number >= 0");
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE || v > max)
    throw InputError(what + ": value '" + text + "' is larger than " + std::to_string(max));
  return v;
}

Pose parse_pose7(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, 7, what);
  const Quat q(v[3], v[4], v[5], v[6]);
  if (std::abs(q.norm() - 1.0) > 1e-3)
    throw InputError(what + ": value '" + text + "': quaternion (qw,qx,qy,qz) has norm " +
                     std::to_string(q.norm()) + ", must be unit length");
  return make_pose(Vec3(v[0], v[1], v[2]), q);
}

BasePose parse_base_pose(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, 3, what);
  return BasePose{v[0], v[1], v[2]};
}

nlohmann::json pose_to_json(const Pose& T) {
  const Quat q(T.linear());
  const Vec3 t = T.translation();
  return {{"position", {t.x(), t.y(), t.z()}}, {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
}

Pose pose_from_json(const nlohmann::json& j) {
  const auto& p = j.at("position");
  const auto& q = j.at("quaternion_wxyz");
  return make_pose(Vec3(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()),
                   Quat(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>()));
}

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
  const std::string old = temp_name(final_dir_ + ".old");
  const bool had_previous = fs::exists(final_dir_, ec);
  if (had_previous) move_or_throw(final_dir_, old);
  try {
    move_or_throw(working_dir_, final_dir_);
  } catch (...) {
    if (had_previous) fs::rename(old, final_dir_, ec);
    throw;
  }
  committed_ = true;
  if (had_previous) fs::remove_all(old, ec);
  unlock();
}

}  // namespace canopy
