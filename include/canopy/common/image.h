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

/// Copies `src` scaled (nearest neighbour) into the w x h rectangle of `dst` at (x0, y0),
/// with a `border` pixel frame of `border_colour` around it; parts outside `dst` are clipped.
template <typename T>
void blit_scaled(const Image<T>& src, int x0, int y0, int w, int h, Image<T>* dst, int border = 0,
                 const T& border_colour = T()) {
  if (src.empty() || w <= 0 || h <= 0) return;
  for (int y = y0 - border; y < y0 + h + border; ++y)
    for (int x = x0 - border; x < x0 + w + border; ++x) {
      if (x < 0 || y < 0 || x >= dst->width || y >= dst->height) continue;
      const bool inside = x >= x0 && y >= y0 && x < x0 + w && y < y0 + h;
      dst->at(x, y) = inside ? src.at((x - x0) * src.width / w, (y - y0) * src.height / h) : border_colour;
    }
}

}  // namespace canopy
