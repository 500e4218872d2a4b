#pragma once
// Minimal row-major image container (row 0 at the top).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy {

/// 8-bit RGB pixel.
struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8& o) const { return r == o.r && g == o.g && b == o.b; }
};

/// Dense image of T, row-major, `width` columns by `height` rows.
template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  std::vector<T> data;

  Image() = default;
  Image(int w, int h, const T& fill = T()) : width(w), height(h), data(static_cast<std::size_t>(w) * h, fill) {}
  T& at(int x, int y) { return data[static_cast<std::size_t>(y) * width + x]; }
  const T& at(int x, int y) const { return data[static_cast<std::size_t>(y) * width + x]; }
  bool empty() const { return data.empty(); }
};

}  // namespace canopy
