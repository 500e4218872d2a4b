#pragma once
// Colour segmentation in HSV (the paper's simulation method; docs/background/evaluation.md). Hue is in
// OpenCV's 0..179 range (degrees / 2), saturation and value in 0..255. A pixel takes the
// class of the first band it falls in, else the background (class 0).

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/common/image.h"
#include "canopy/common/params.h"

namespace canopy::perception {

/// HSV of one pixel: h in [0, 180), s and v in [0, 255].
struct Hsv {
  int h = 0, s = 0, v = 0;
};

/// OpenCV-compatible RGB to HSV (8-bit, hue halved).
Hsv rgb_to_hsv(const Rgb8& c);

/// One colour band that maps to a class; bounds are inclusive.
struct HsvBand {
  std::string class_name;
  int h_min = 0, h_max = 179;
  int s_min = 0, s_max = 255;
  int v_min = 0, v_max = 255;
  bool contains(const Hsv& p) const {
    return p.h >= h_min && p.h <= h_max && p.s >= s_min && p.s <= s_max && p.v >= v_min && p.v <= v_max;
  }
  template <class A>
  void visit(A& a) {
    a.required("class", class_name, "Class of the pixels in the band");
    a("h_min", h_min, limits::in(0, 179), "Hue from (0..179, degrees / 2)");
    a("h_max", h_max, limits::in(0, 179), "Hue to");
    a("s_min", s_min, limits::in(0, 255), "Saturation from");
    a("s_max", s_max, limits::in(0, 255), "Saturation to");
    a("v_min", v_min, limits::in(0, 255), "Value from");
    a("v_max", v_max, limits::in(0, 255), "Value to");
    a.check(h_min <= h_max, "h_max", "must be >= h_min");
    a.check(s_min <= s_max, "s_max", "must be >= s_min");
    a.check(v_min <= v_max, "v_max", "must be >= v_min");
  }
  bool operator==(const HsvBand& o) const { return same_params(*this, o); }
};

/// The bands, first match wins. Defaults: the prototype's red and green bands plus a yellow
/// fruit band (the default world has yellow fruit; green fruit segments as leaf).
struct ColorSegmentationParams {
  std::vector<HsvBand> bands = {
      {"fruit", 0, 20, 50, 255, 50, 255},     // red and orange
      {"fruit", 160, 179, 50, 255, 50, 255},  // red (hue wraps)
      {"fruit", 21, 35, 100, 255, 50, 255},   // yellow: saturated only
      {"leaf", 40, 80, 20, 255, 20, 255},     // green
  };

  template <class A>
  void visit(A& a) {
    a.list("bands", bands, "HSV bands, first match wins; a pixel in none is background");
  }
  bool operator==(const ColorSegmentationParams& o) const { return bands == o.bands; }
};

/// Labels every pixel of `rgb` with a class index of `classes` (bands naming classes that
/// are not in the list throw InputError naming `where`).
Image<std::uint8_t> segment_by_color(const Image<Rgb8>& rgb, const ColorSegmentationParams& params,
                                     const SemanticClasses& classes, const std::string& where = "color segmentation");

}  // namespace canopy::perception
