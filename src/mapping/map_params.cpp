#include "canopy/mapping/map_params.h"

#include <cmath>

#include "canopy/common/error.h"

namespace canopy::mapping {

SemanticMapParams SemanticMapParams::from_yaml(YamlReader& y) {
  SemanticMapParams p;
  auto real = [&](const std::string& key, double fallback) {
    const double v = y.get(key, fallback);
    y.check(std::isfinite(v), key, "must be a finite number");
    return v;
  };
  p.resolution_m = real("resolution_m", p.resolution_m);
  p.hit_logodds = static_cast<float>(real("hit_logodds", p.hit_logodds));
  p.pass_logodds = static_cast<float>(real("pass_logodds", p.pass_logodds));
  p.clamp_min_logodds = static_cast<float>(real("clamp_min_logodds", p.clamp_min_logodds));
  p.clamp_max_logodds = static_cast<float>(real("clamp_max_logodds", p.clamp_max_logodds));
  p.max_range_m = real("max_range_m", p.max_range_m);
  p.ray_range_m = real("ray_range_m", p.ray_range_m);
  p.unseen_logodds = static_cast<float>(real("unseen_logodds", p.unseen_logodds));
  p.prune = y.get("prune", p.prune);
  p.entropy_categories = y.get_choice("entropy_categories", p.entropy_categories, kEntropyCategoriesNames);
  p.threads = y.get("threads", p.threads);
  y.check(p.resolution_m >= 0.001 && p.resolution_m <= 1.0, "resolution_m", "must be in [0.001, 1] m");
  y.check(p.hit_logodds > 0.f, "hit_logodds", "must be > 0");
  y.check(p.pass_logodds < 0.f, "pass_logodds", "must be < 0");
  y.check(p.clamp_min_logodds < 0.f, "clamp_min_logodds", "must be < 0");
  y.check(p.clamp_max_logodds > 0.f, "clamp_max_logodds", "must be > 0");
  y.check(p.max_range_m > 0.0, "max_range_m", "must be > 0");
  y.check(p.ray_range_m > 0.0, "ray_range_m", "must be > 0");
  y.check(p.unseen_logodds >= p.clamp_min_logodds && p.unseen_logodds <= p.clamp_max_logodds, "unseen_logodds",
          "must lie within [clamp_min_logodds, clamp_max_logodds]");
  y.check(p.hit_logodds < p.clamp_max_logodds, "hit_logodds", "must be below clamp_max_logodds");
  y.check(p.pass_logodds > p.clamp_min_logodds, "pass_logodds", "must be above clamp_min_logodds");
  y.check(p.threads >= 0 && p.threads <= 256, "threads", "must be in [0, 256]");
  return p;
}

YAML::Node SemanticMapParams::to_yaml() const {
  YAML::Node n;
  n["resolution_m"] = resolution_m;
  // Floats go out as the double they convert to, so reading them back is exact.
  n["hit_logodds"] = double(hit_logodds);
  n["pass_logodds"] = double(pass_logodds);
  n["clamp_min_logodds"] = double(clamp_min_logodds);
  n["clamp_max_logodds"] = double(clamp_max_logodds);
  n["max_range_m"] = max_range_m;
  n["ray_range_m"] = ray_range_m;
  n["unseen_logodds"] = double(unseen_logodds);
  n["prune"] = prune;
  n["entropy_categories"] = to_string(entropy_categories);
  n["threads"] = threads;
  return n;
}

void SemanticMapParams::validate(const std::string& where) const {
  YAML::Emitter e;
  e << to_yaml();
  YamlReader y = YamlReader::load_string(e.c_str(), where);
  from_yaml(y);
}

bool SemanticMapParams::operator==(const SemanticMapParams& o) const {
  return resolution_m == o.resolution_m && hit_logodds == o.hit_logodds && pass_logodds == o.pass_logodds &&
         clamp_min_logodds == o.clamp_min_logodds && clamp_max_logodds == o.clamp_max_logodds &&
         max_range_m == o.max_range_m && ray_range_m == o.ray_range_m && unseen_logodds == o.unseen_logodds &&
         prune == o.prune && entropy_categories == o.entropy_categories && threads == o.threads;
}

}  // namespace canopy::mapping
