#include "canopy/common/png_io.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"

namespace canopy {

namespace {

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};

// Writes rows through libpng into a temporary file, then renames it into place.
template <typename RowFn>
void write_png_rows(const std::string& path, int width, int height, int bit_depth, int color_type,
                    RowFn&& row_fn) {
  const std::string tmp = unique_temp_path(path);
  std::unique_ptr<FILE, FileCloser> f(std::fopen(tmp.c_str(), "wb"));
  if (!f) throw IoError("cannot write " + path + ": " + std::strerror(errno));
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
    const int err = errno;
    png_destroy_write_struct(&png, &info);
    f.reset();
    std::remove(tmp.c_str());
    throw IoError("cannot write " + path + (err ? ": " + std::string(std::strerror(err)) : std::string(" (libpng)")));
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
  // A full disk shows at the flush or the close: the file is not published.
  const bool flushed = std::fflush(f.get()) == 0;
  int err = flushed ? 0 : errno;
  if (std::fclose(f.release()) != 0 && err == 0) err = errno;
  if (!flushed || err != 0) {
    std::remove(tmp.c_str());
    throw IoError("cannot write " + path + ": " + std::strerror(err ? err : EIO));
  }
  move_temp_into_place(tmp, path);
}

struct PngRead {
  int width = 0, height = 0, bit_depth = 0, color_type = 0, channels = 0;
  std::vector<png_byte> pixels;  // rows packed
  size_t rowbytes = 0;
};

// PNG bytes in memory, read by libpng through png_set_read_fn.
struct PngMemory {
  std::string_view bytes;
  std::size_t pos = 0;
};

// Reads a PNG from the open file `f` (its signature already read) or, when `f` is null, from
// `memory`; `path` names it in errors.
PngRead read_png_source(const std::string& path, FILE* f, PngMemory* memory);

PngRead read_png_raw(const std::string& path) {
  std::unique_ptr<FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f) throw InputError(path + ": cannot open file");
  png_byte sig[8];
  if (std::fread(sig, 1, 8, f.get()) != 8 || png_sig_cmp(sig, 0, 8) != 0)
    throw InputError(path + ": not a PNG file");
  return read_png_source(path, f.get(), nullptr);
}

PngRead read_png_memory(std::string_view bytes, const std::string& what) {
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    throw InputError(what + ": not a PNG file");
  PngMemory memory{bytes, 8};
  return read_png_source(what, nullptr, &memory);
}

PngRead read_png_source(const std::string& path, FILE* f, PngMemory* memory) {
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
  if (f) {
    png_init_io(png, f);
  } else {
    png_set_read_fn(png, memory, [](png_structp p, png_bytep out, png_size_t n) {
      auto* m = static_cast<PngMemory*>(png_get_io_ptr(p));
      if (n > m->bytes.size() - m->pos) png_error(p, "the PNG data ends early");
      std::memcpy(out, m->bytes.data() + m->pos, n);
      m->pos += n;
    });
  }
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

namespace {
Image<Rgb8> rgb_of(const PngRead& raw, const std::string& path) {
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

Image<std::uint16_t> gray16_of(const PngRead& raw, const std::string& path) {
  if (raw.bit_depth != 16 || raw.channels != 1) throw InputError(path + ": expected a 16-bit grayscale PNG");
  Image<std::uint16_t> img(raw.width, raw.height);
  for (int y = 0; y < raw.height; ++y)
    for (int x = 0; x < raw.width; ++x) {
      const png_byte* p = raw.pixels.data() + raw.rowbytes * y + 2 * x;
      img.at(x, y) = static_cast<std::uint16_t>(p[0] | (p[1] << 8));
    }
  return img;
}

}  // namespace

Image<Rgb8> read_png_rgb(const std::string& path) { return rgb_of(read_png_raw(path), path); }
Image<std::uint16_t> read_png_gray16(const std::string& path) { return gray16_of(read_png_raw(path), path); }
Image<Rgb8> decode_png_rgb(std::string_view bytes, const std::string& what) {
  return rgb_of(read_png_memory(bytes, what), what);
}
Image<std::uint16_t> decode_png_gray16(std::string_view bytes, const std::string& what) {
  return gray16_of(read_png_memory(bytes, what), what);
}

std::optional<std::pair<int, int>> png_declared_size(std::string_view bytes) {
  // The signature (8 bytes), then the IHDR chunk: length, "IHDR", width and height big-endian.
  if (bytes.size() < 24 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0 ||
      bytes.substr(12, 4) != "IHDR")
    return std::nullopt;
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<std::uint8_t>(bytes[at + i]);
    return v;
  };
  const std::uint32_t w = be32(16), h = be32(20);
  if (w == 0 || h == 0 || w > kMaxImageSidePx || h > kMaxImageSidePx) return std::nullopt;
  return std::make_pair(static_cast<int>(w), static_cast<int>(h));
}

}  // namespace canopy
