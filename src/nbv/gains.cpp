#include "canopy/nbv/gains.h"

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/random.h"

namespace canopy::nbv {

namespace {

class Osamcep final : public GainFunction {
 public:
  explicit Osamcep(const GainParams& p)
      : max_dist2_(float(p.max_dist_m * p.max_dist_m)), per_segment_end_(p.proximity == Proximity::kPerSegmentEnd) {}
  std::string name() const override { return "osamcep"; }
  double ray_gain(const RayVoxel* v, std::size_t n) const override {
    double g = 0.0, visible = 1.0;
    float seg_end_d2 = 0.f;  // per_segment_end: distance of the current run's last voxel
    for (std::size_t i = 0; i < n; ++i) {
      if (per_segment_end_ && (i == 0 || v[i].id != v[i - 1].id)) {
        std::size_t j = i;
        while (j + 1 < n && v[j + 1].id == v[i].id) ++j;
        seg_end_d2 = v[j].dist2_m2;
      }
      const VoxelInfo& x = *v[i].info;
      const float d2 = per_segment_end_ ? seg_end_d2 : v[i].dist2_m2;
      if ((!x.known || x.is_target) && d2 < max_dist2_) g += visible * x.entropy;
      visible *= 1.0 - x.p_occ;
    }
    return g;
  }

 private:
  float max_dist2_;
  bool per_segment_end_;
};

class AverageEntropy final : public GainFunction {
 public:
  explicit AverageEntropy(const GainParams& p) : stop_(float(p.ae_stop_occupancy)) {}
  std::string name() const override { return "ae"; }
  double ray_gain(const RayVoxel* v, std::size_t n) const override {
    double g = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (v[i].info->known && v[i].info->p_occ >= stop_) break;
      g += v[i].info->binary_entropy;
    }
    return g;
  }

 private:
  float stop_;
};

// UVC and UVPC share Zaenker's unknown/blocking rule.
class UnknownCount final : public GainFunction {
 public:
  UnknownCount(const GainParams& p, bool proximity)
      : low_(float(p.unknown_low)), high_(float(p.unknown_high)), max_dist_(float(p.max_dist_m)),
        max_dist2_(float(p.max_dist_m * p.max_dist_m)), base_(p.uvpc_base_weight), proximity_(proximity) {}
  std::string name() const override { return proximity_ ? "uvpc" : "uvc"; }
  double ray_gain(const RayVoxel* v, std::size_t n) const override {
    double g = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const VoxelInfo& x = *v[i].info;
      if (x.known && x.p_occ > high_) break;
      const bool unknown = !x.known || x.p_occ > low_;
      if (!unknown) continue;
      if (!proximity_) {
        g += 1.0;
      } else if (v[i].dist2_m2 < max_dist2_) {
        g += base_ + (double(max_dist_) - std::sqrt(double(v[i].dist2_m2))) / max_dist_;
      }
    }
    return g;
  }

 private:
  float low_, high_, max_dist_, max_dist2_;
  double base_;
  bool proximity_;
};

class OcclusionAwareEntropy final : public GainFunction {
 public:
  std::string name() const override { return "oae"; }
  double ray_gain(const RayVoxel* v, std::size_t n) const override {
    double g = 0.0, visible = 1.0;
    for (std::size_t i = 0; i < n; ++i) {
      g += visible * v[i].info->binary_entropy;
      visible *= 1.0 - v[i].info->p_occ;
    }
    return g;
  }
};

// Sum over hit classes k of p_k kl_hit_k (the hit term of one cell), and p(no hit) = p_free.
inline double hit_term(const VoxelInfo& x) {
  double a = 0.0;
  for (int k = 0; k + 1 < VoxelInfo::kMaxCategories; ++k) a += double(x.prob[k + 1]) * x.kl_hit[k];
  return a;
}

class MutualInformation final : public GainFunction {
 public:
  std::string name() const override { return "mi"; }
  // Outcomes: the ray passes cells 1..n-1 (free updates) and hits cell n with class k, or passes
  // every cell. I = sum_outcomes p(outcome) sum_cells KL(posterior || prior). Over a segment of L
  // identical cells (free probability q, hit term a = sum_k p_k KL_k, s = 1 - q) entered with
  // reach probability P and accumulated free KL F, the hits contribute
  //   P [ (s F + a) G0 + s f0 G1 ],  G0 = sum_{j<L} q^j,  G1 = sum_{j<L} j q^j,
  // after which P *= q^L and F += L f0.
  double ray_gain(const RayVoxel* v, std::size_t n) const override {
    double mi = 0.0, reach = 1.0, free_kl = 0.0;
    std::size_t i = 0;
    while (i < n) {
      std::size_t j = i + 1;
      while (j < n && v[j].id == v[i].id) ++j;
      const VoxelInfo& x = *v[i].info;
      const double len = double(j - i);
      // Normalise the segment's categories (guards float rounding of the stored distribution).
      double total = 0.0;
      for (int k = 0; k < VoxelInfo::kMaxCategories; ++k) total += x.prob[k];
      const double q = total > 0.0 ? x.prob[0] / total : 0.0;
      const double s = 1.0 - q;
      const double a = total > 0.0 ? hit_term(x) / total : 0.0;
      double g0, g1, qL;
      if (1.0 - q < 1e-6 || q < 1e-6 || len <= 4.0) {
        g0 = 0.0;
        g1 = 0.0;
        double qj = 1.0;
        for (std::size_t m = 0; m < j - i; ++m) {
          g0 += qj;
          g1 += double(m) * qj;
          qj *= q;
        }
        qL = qj;
      } else {
        qL = std::pow(q, len);
        g0 = (1.0 - qL) / (1.0 - q);
        g1 = q * (1.0 - len * qL / q + (len - 1.0) * qL) / ((1.0 - q) * (1.0 - q));
      }
      mi += reach * ((s * free_kl + a) * g0 + s * double(x.kl_free) * g1);
      reach *= qL;
      free_kl += len * x.kl_free;
      i = j;
    }
    mi += reach * free_kl;  // no hit: every cell seen free
    return mi;
  }
};

class RandomScore final : public GainFunction {
 public:
  std::string name() const override { return "rs"; }
  double ray_gain(const RayVoxel*, std::size_t) const override { return 0.0; }
  bool uses_rays() const override { return false; }
  double view_gain(double, std::uint64_t view_seed) const override {
    Rng rng(view_seed);
    return 1.0 - rng.uniform();  // (0, 1]: never "done"
  }
};

}  // namespace

double mutual_information_per_cell(const RayVoxel* v, std::size_t n) {
  double mi = 0.0, reach = 1.0, free_kl = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const VoxelInfo& x = *v[i].info;
    double total = 0.0;
    for (int k = 0; k < VoxelInfo::kMaxCategories; ++k) total += x.prob[k];
    for (int k = 0; k + 1 < VoxelInfo::kMaxCategories; ++k)
      mi += reach * (x.prob[k + 1] / total) * (free_kl + x.kl_hit[k]);
    reach *= x.prob[0] / total;
    free_kl += x.kl_free;
  }
  return mi + reach * free_kl;
}

const std::vector<GainEntry>& gain_registry() {
  static const std::vector<GainEntry> registry = {
      {"osamcep", "occlusion- and semantic-aware multi-class entropy with proximity (ours)",
       [](const GainParams& p) { return std::unique_ptr<GainFunction>(new Osamcep(p)); }, /*uses_proximity=*/true},
      {"ae", "average entropy (Delmerico 2018), summed until an occupied voxel",
       [](const GainParams& p) { return std::unique_ptr<GainFunction>(new AverageEntropy(p)); }},
      {"uvc", "unknown voxel count",
       [](const GainParams& p) { return std::unique_ptr<GainFunction>(new UnknownCount(p, false)); }},
      {"uvpc", "unknown voxels with proximity count (Zaenker 2021)",
       [](const GainParams& p) { return std::unique_ptr<GainFunction>(new UnknownCount(p, true)); }},
      {"oae", "occlusion-aware entropy (Delmerico 2018)",
       [](const GainParams&) { return std::unique_ptr<GainFunction>(new OcclusionAwareEntropy()); }},
      {"mi", "SSMI Shannon mutual information (Asgharivaskasi 2023)",
       [](const GainParams&) { return std::unique_ptr<GainFunction>(new MutualInformation()); }},
      {"rs", "random score",
       [](const GainParams&) { return std::unique_ptr<GainFunction>(new RandomScore()); }},
  };
  return registry;
}

std::vector<std::string> gain_names() {
  std::vector<std::string> names;
  for (const GainEntry& e : gain_registry()) names.push_back(e.name);
  return names;
}

std::unique_ptr<GainFunction> make_gain(const std::string& name, const GainParams& params, const std::string& where) {
  std::string valid;
  for (const GainEntry& e : gain_registry()) {
    if (e.name == name) return e.make(params);
    valid += (valid.empty() ? "" : ", ") + e.name;
  }
  throw InputError(where + ": unknown gain '" + name + "' (valid: " + valid + ")");
}

}  // namespace canopy::nbv
