#pragma once
// PNG images: atomic writers and size-checked readers of 8-bit RGB and 16-bit grayscale.

#include <cstdint>
#include <string>

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

}  // namespace canopy
