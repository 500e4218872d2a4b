#include <cmath>

#include "canopy/common/error.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::perception {

ExtractorParams ExtractorParams::from_yaml(YamlReader& y) {
  ExtractorParams p;
  p.source = y.get_choice("source", p.source, kLabelSourceNames);
  YamlReader c = y.child("color");
  p.color = ColorSegmentationParams::from_yaml(c);
  c.finish();
  p.p_gt = y.get("p_gt", p.p_gt);
  y.check(std::isfinite(p.p_gt) && p.p_gt >= 0.0 && p.p_gt <= 1.0, "p_gt", "must be in [0, 1]");
  p.noise = y.get_choice("noise", p.noise, kNoiseModelNames);
  p.depth_noise_k = y.get("depth_noise_k", p.depth_noise_k);
  y.check(std::isfinite(p.depth_noise_k) && p.depth_noise_k >= 0.0, "depth_noise_k", "must be >= 0");
  p.seed = y.get("seed", p.seed);
  return p;
}

YAML::Node ExtractorParams::to_yaml() const {
  YAML::Node n;
  n["source"] = to_string(source);
  n["color"] = color.to_yaml();
  n["p_gt"] = p_gt;
  n["noise"] = to_string(noise);
  n["depth_noise_k"] = depth_noise_k;
  n["seed"] = seed;
  return n;
}

bool ExtractorParams::operator==(const ExtractorParams& o) const {
  return source == o.source && color == o.color && p_gt == o.p_gt && noise == o.noise && depth_noise_k == o.depth_noise_k &&
         seed == o.seed;
}

}  // namespace canopy::perception
