#include "canopy/perception/color_segmentation.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"

namespace canopy::perception {

Hsv rgb_to_hsv(const Rgb8& c) {
  // OpenCV's COLOR_RGB2HSV for 8-bit images: V = max, S = 255 (V - min) / V,
  // H = 30 (G - B) / (V - min) etc. in degrees / 2, rounded.
  const int r = c.r, g = c.g, b = c.b;
  const int v = std::max(r, std::max(g, b));
  const int mn = std::min(r, std::min(g, b));
  const int diff = v - mn;
  Hsv out;
  out.v = v;
  out.s = v == 0 ? 0 : static_cast<int>(std::lround(255.0 * diff / v));
  if (diff == 0) return out;
  double h;
  if (v == r) h = 60.0 * (g - b) / diff;
  else if (v == g) h = 120.0 + 60.0 * (b - r) / diff;
  else h = 240.0 + 60.0 * (r - g) / diff;
  if (h < 0) h += 360.0;
  out.h = static_cast<int>(std::lround(h / 2.0));
  if (out.h >= 180) out.h -= 180;
  return out;
}

Image<std::uint8_t> segment_by_color(const Image<Rgb8>& rgb, const ColorSegmentationParams& params,
                                     const SemanticClasses& classes, const std::string& where) {
  std::vector<int> band_class;
  for (const HsvBand& b : params.bands) {
    const int c = classes.index_of(b.class_name);
    if (c < 0) throw InputError(where + ": colour band class '" + b.class_name + "' is not in the class list");
    band_class.push_back(c);
  }
  Image<std::uint8_t> out(rgb.width, rgb.height, 0);
  // HSV depends only on the colour; renders have few distinct colours per run of pixels.
  Rgb8 last{1, 2, 3};
  std::uint8_t last_label = 0;
  bool have_last = false;
  for (std::size_t i = 0; i < rgb.data.size(); ++i) {
    const Rgb8& c = rgb.data[i];
    if (!have_last || !(c == last)) {
      const Hsv hsv = rgb_to_hsv(c);
      last_label = 0;
      for (std::size_t k = 0; k < params.bands.size(); ++k) {
        if (params.bands[k].contains(hsv)) {
          last_label = static_cast<std::uint8_t>(band_class[k]);
          break;
        }
      }
      last = c;
      have_last = true;
    }
    out.data[i] = last_label;
  }
  return out;
}

}  // namespace canopy::perception
