#pragma once
// PNG images: atomic writers and size-checked readers of 8-bit RGB and 16-bit grayscale.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "canopy/common/image.h"

namespace canopy {

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
/// The same from a PNG file's bytes in memory (a ROS CompressedImage); `what` names it in errors.
Image<Rgb8> decode_png_rgb(std::string_view bytes, const std::string& what);
Image<std::uint16_t> decode_png_gray16(std::string_view bytes, const std::string& what);
/// The width and height a PNG's header declares, read without decoding; nullopt when the bytes
/// do not start as a PNG does or declare a side of 0 or beyond kMaxImageSidePx.
std::optional<std::pair<int, int>> png_declared_size(std::string_view bytes);

}  // namespace canopy
