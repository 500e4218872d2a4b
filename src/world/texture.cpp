#include "canopy/world/texture.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "canopy/common/error.h"

namespace canopy::world {

namespace {

// A TGA has no magic number: it is the format stb_image falls back to when the first bytes are
// none of the others' signatures and the image type is one TGA defines.
bool looks_like_tga(const std::string& b) {
  if (b.size() < 18) return false;
  const auto u = [&](std::size_t i) { return static_cast<unsigned char>(b[i]); };
  if (b.compare(0, 4, "\x89PNG") == 0 || (u(0) == 0xFF && u(1) == 0xD8) || b.compare(0, 2, "BM") == 0 ||
      b.compare(0, 3, "GIF") == 0 || b.compare(0, 4, "8BPS") == 0 || b.compare(0, 2, "#?") == 0 ||
      (u(0) == 'P' && (u(1) == '5' || u(1) == '6')))
    return false;
  const int type = u(2);
  return type == 1 || type == 2 || type == 3 || type == 9 || type == 10 || type == 11;
}

// stb_image reads past the end of a TGA as zeros (black texels) without a word: a file cut
// short would bake black into the plant's colour. Returns why the pixel data are incomplete
// ("" when they are whole).
std::string tga_truncation(const std::string& b) {
  const auto u = [&](std::size_t i) { return static_cast<unsigned char>(b[i]); };
  const std::size_t id_len = u(0), cmap_type = u(1), type = u(2);
  const std::size_t cmap_len = u(5) | (u(6) << 8), cmap_bits = u(7);
  const std::size_t w = u(12) | (u(13) << 8), h = u(14) | (u(15) << 8), bpp = u(16);
  const std::size_t pixel_bytes = (bpp + 7) / 8;
  std::size_t at = 18 + id_len + (cmap_type ? cmap_len * ((cmap_bits + 7) / 8) : 0);
  const std::size_t pixels = w * h;
  const auto cut = [&](std::size_t need) {
    return "truncated TGA: " + std::to_string(b.size()) + " bytes, its header needs at least " + std::to_string(need) +
           " for " + std::to_string(w) + " x " + std::to_string(h) + " px";
  };
  if (type < 8) {  // uncompressed
    const std::size_t need = at + pixels * pixel_bytes;
    return b.size() < need ? cut(need) : "";
  }
  for (std::size_t done = 0; done < pixels;) {  // run-length encoded: walk the packets
    if (at >= b.size()) return cut(at + 1);
    const std::size_t head = u(at++), n = (head & 0x7F) + 1;
    at += (head & 0x80) ? pixel_bytes : n * pixel_bytes;
    if (at > b.size()) return cut(at);
    done += n;
  }
  return "";
}

}  // namespace

Image<Rgb8> decode_image(const std::string& bytes, const std::string& what) {
  if (bytes.empty() || bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw InputError(what + ": empty or too large to be a texture");
  if (looks_like_tga(bytes))
    if (const std::string why = tga_truncation(bytes); !why.empty()) throw InputError(what + ": " + why);
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(data, size, &w, &h, &channels))
    throw InputError(what + ": not an image stb_image can read (" + std::string(stbi_failure_reason()) + ")");
  if (w < 1 || h < 1 || w > kMaxTextureSidePx || h > kMaxTextureSidePx)
    throw InputError(what + ": " + std::to_string(w) + " x " + std::to_string(h) + " px (at most " +
                     std::to_string(kMaxTextureSidePx) + " px a side)");
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_memory(data, size, &w, &h, &channels, 3), stbi_image_free);
  if (!pixels) throw InputError(what + ": cannot decode the image (" + std::string(stbi_failure_reason()) + ")");
  Image<Rgb8> image(w, h);
  for (size_t i = 0; i < image.data.size(); ++i)
    image.data[i] = Rgb8{pixels.get()[3 * i], pixels.get()[3 * i + 1], pixels.get()[3 * i + 2]};
  return image;
}

namespace {

// Texel (column, row from the top) holding the point (u, v), UVs wrapping.
size_t texel_at(int width, int height, double u, double v) {
  const double fu = u - std::floor(u), fv = v - std::floor(v);
  const int x = std::clamp(static_cast<int>(fu * width), 0, width - 1);
  const int y = std::clamp(static_cast<int>((1.0 - fv) * height), 0, height - 1);
  return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
}

}  // namespace

std::vector<double> texel_weights(int width, int height, const std::vector<FaceUv>& uv) {
  CANOPY_CHECK(width > 0 && height > 0, "texel_weights of an empty image");
  std::vector<double> w(static_cast<size_t>(width) * static_cast<size_t>(height), 0.0);
  for (const FaceUv& f : uv) {
    // Texture space in texels: x = u W, y = v H (y up); texel (i, j) has its centre at (i + 0.5, j + 0.5).
    std::array<Vec2, 3> p;
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      p[static_cast<size_t>(k)] = Vec2(f[static_cast<size_t>(k)].x() * width, f[static_cast<size_t>(k)].y() * height);
      finite = finite && p[static_cast<size_t>(k)].allFinite();
    }
    if (!finite) continue;
    const double area2 = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    const double area = 0.5 * std::abs(area2);
    const Vec2 lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
    const double span = (std::floor(hi.x()) - std::floor(lo.x()) + 1) * (std::floor(hi.y()) - std::floor(lo.y()) + 1);
    const Vec2 centroid = (p[0] + p[1] + p[2]) / 3.0;
    if (area2 == 0.0) continue;
    if (span > static_cast<double>(kMaxTexelsPerFace)) {
      // A face over a huge span of repeats: a grid of barycentric samples, each its share of the area.
      const int n = static_cast<int>(std::sqrt(static_cast<double>(kMaxTexelsPerFace)));
      long count = 0;
      std::vector<size_t> hits;
      for (int a = 0; a < n; ++a)
        for (int b = 0; a + b < n; ++b) {
          const double s = (a + 1.0 / 3.0) / n, t = (b + 1.0 / 3.0) / n;
          const Vec2 q = p[0] + s * (p[1] - p[0]) + t * (p[2] - p[0]);
          hits.push_back(texel_at(width, height, q.x() / width, q.y() / height));
          ++count;
        }
      for (size_t h : hits) w[h] += area / static_cast<double>(count);
      continue;
    }
    long inside = 0;
    const long x0 = static_cast<long>(std::floor(lo.x())), x1 = static_cast<long>(std::floor(hi.x()));
    const long y0 = static_cast<long>(std::floor(lo.y())), y1 = static_cast<long>(std::floor(hi.y()));
    auto edge = [](const Vec2& a, const Vec2& b, const Vec2& q) {
      return (b.x() - a.x()) * (q.y() - a.y()) - (b.y() - a.y()) * (q.x() - a.x());
    };
    const double sign = area2 > 0 ? 1.0 : -1.0;
    for (long j = y0; j <= y1; ++j)
      for (long i = x0; i <= x1; ++i) {
        const Vec2 q(i + 0.5, j + 0.5);
        if (sign * edge(p[0], p[1], q) < 0 || sign * edge(p[1], p[2], q) < 0 || sign * edge(p[2], p[0], q) < 0) continue;
        w[texel_at(width, height, q.x() / width, q.y() / height)] += 1.0;
        ++inside;
      }
    if (inside == 0) w[texel_at(width, height, centroid.x() / width, centroid.y() / height)] += area;
  }
  return w;
}

std::array<float, 3> mean_color(const Image<Rgb8>& image, const std::vector<double>& weights) {
  CANOPY_CHECK(weights.size() == image.data.size(), "mean_color: one weight per texel");
  double sum[3] = {0, 0, 0}, total = 0.0;
  for (size_t i = 0; i < image.data.size(); ++i) total += weights[i];
  const bool uniform = !(total > 0.0);
  for (size_t i = 0; i < image.data.size(); ++i) {
    const double wi = uniform ? 1.0 : weights[i];
    sum[0] += wi * image.data[i].r, sum[1] += wi * image.data[i].g, sum[2] += wi * image.data[i].b;
  }
  if (uniform) total = static_cast<double>(image.data.size());
  return {static_cast<float>(sum[0] / total / 255.0), static_cast<float>(sum[1] / total / 255.0),
          static_cast<float>(sum[2] / total / 255.0)};
}

}  // namespace canopy::world
