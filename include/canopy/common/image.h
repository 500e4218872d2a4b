#pragma once
// Minimal row-major image container (row 0 at the top).

#include <algorithm>
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
  // Row by row, the source row and the clipped spans computed once (a video frame blits three
  // insets per frame).
  const int xa = std::max(0, x0 - border), xb = std::min(dst->width, x0 + w + border);
  const int ya = std::max(0, y0 - border), yb = std::min(dst->height, y0 + h + border);
  if (xa >= xb) return;  // wholly left or right of the target
  const int ia = std::min(xb, std::max(xa, x0)), ib = std::max(ia, std::min(xb, x0 + w));
  for (int y = ya; y < yb; ++y) {
    T* row = &dst->at(0, y);
    if (y < y0 || y >= y0 + h) {
      std::fill(row + xa, row + xb, border_colour);
      continue;
    }
    const T* from = &src.at(0, (y - y0) * src.height / h);
    std::fill(row + xa, row + ia, border_colour);
    if (w == src.width)
      std::copy(from + (ia - x0), from + (ib - x0), row + ia);
    else
      for (int x = ia; x < ib; ++x) row[x] = from[(x - x0) * src.width / w];
    std::fill(row + ib, row + std::max(ib, xb), border_colour);
  }
}

}  // namespace canopy
