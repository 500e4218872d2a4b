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

bool HsvBand::operator==(const HsvBand& o) const {
  return class_name == o.class_name && h_min == o.h_min && h_max == o.h_max && s_min == o.s_min &&
         s_max == o.s_max && v_min == o.v_min && v_max == o.v_max;
}

ColorSegmentationParams ColorSegmentationParams::from_yaml(YamlReader& y) {
  ColorSegmentationParams p;
  if (!y.has("bands")) {
    y.get<std::string>("bands", "");  // mark as read
    return p;
  }
  const YAML::Node list = y.require<YAML::Node>("bands");
  y.check(list.IsSequence() && list.size() > 0, "bands", "must be a non-empty list of bands");
  p.bands.clear();
  for (std::size_t i = 0; i < list.size(); ++i) {
    YamlReader b(list[i], y.file(), y.key_path("bands") + "[" + std::to_string(i) + "]");
    HsvBand band;
    band.class_name = b.require<std::string>("class");
    auto bound = [&](const std::string& key, int fallback, int max) {
      const int v = b.get(key, fallback);
      b.check(v >= 0 && v <= max, key, "must be in [0, " + std::to_string(max) + "]");
      return v;
    };
    band.h_min = bound("h_min", band.h_min, 179);
    band.h_max = bound("h_max", band.h_max, 179);
    band.s_min = bound("s_min", band.s_min, 255);
    band.s_max = bound("s_max", band.s_max, 255);
    band.v_min = bound("v_min", band.v_min, 255);
    band.v_max = bound("v_max", band.v_max, 255);
    b.check(band.h_min <= band.h_max, "h_max", "must be >= h_min");
    b.check(band.s_min <= band.s_max, "s_max", "must be >= s_min");
    b.check(band.v_min <= band.v_max, "v_max", "must be >= v_min");
    b.finish();
    p.bands.push_back(band);
  }
  return p;
}

YAML::Node ColorSegmentationParams::to_yaml() const {
  YAML::Node n;
  for (const HsvBand& b : bands) {
    YAML::Node e;
    e["class"] = b.class_name;
    e["h_min"] = b.h_min;
    e["h_max"] = b.h_max;
    e["s_min"] = b.s_min;
    e["s_max"] = b.s_max;
    e["v_min"] = b.v_min;
    e["v_max"] = b.v_max;
    n["bands"].push_back(e);
  }
  return n;
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
