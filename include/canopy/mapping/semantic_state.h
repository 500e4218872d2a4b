#pragma once
// The payload of one semantic-octree voxel and SSMI's update rules (docs/background/semantic_map.md).
//
// A voxel stores log-odds relative to the "free" category for at most three classes (the
// strongest seen so far, sorted strongest first) plus an "others" bucket that stands for
// every class not stored. A voxel that exists but was never hit has no stored class and
// l_others = 0 (p_occ = 0.5, OctoMap's prior), so one pass-through gives l_others = phi and a
// first hit of class k gives l_k = l_others + psi.
//
// Distributions reported by this header are over the stored vector
//   {free, stored classes..., others},
// which is what SSMI's entropy and mutual information use. Per-class probabilities split the
// "others" mass equally among the classes that are not stored.

#include <array>
#include <cstdint>
#include <string>

#include "canopy/common/enum_names.h"

namespace canopy::mapping {

/// The categories the multi-class entropy H(x) runs over (docs/background/semantic_map.md and evaluation.md):
///  - kPaper: {free} and the K classes of the map (the paper's H). Stored classes keep their
///    log-odds; unstored classes share the "others" mass equally; when every class is
///    stored the "others" slot holds no class and carries no mass. An unknown voxel is
///    SSMI's prior chi = [0, u, ..., u] with K class entries (K = 3: about ln 4 nats).
///  - kPrototype: the released code's 5-entry vector softmax([0, l_1, l_2, l_3, l_others])
///    whatever K is; an empty slot holds l_others. Unknown: [0, u, u, u, u] (about ln 5).
enum class EntropyCategories { kPaper, kPrototype };
inline constexpr EnumName<EntropyCategories> kEntropyCategoriesNames[] = {{EntropyCategories::kPaper, "paper"},
                                                                          {EntropyCategories::kPrototype, "prototype"}};

/// "paper" / "prototype".
std::string to_string(EntropyCategories c);

/// Log-odds increments and clamps of the SSMI rules (psi, phi, +-9.21).
struct UpdateRule {
  float hit = 1.0f;        ///< psi: added to the observed class.
  float pass = -0.1f;      ///< phi: added to every other entry (and to all on pass-through).
  float min = -9.21f;      ///< Lower clamp (probability ~1e-4).
  float max = 9.21f;       ///< Upper clamp (probability ~0.9999).
};

/// Semantic state of one voxel: 20 bytes, trivially copyable, compared bytewise by value.
struct SemanticState {
  static constexpr int kSlots = 3;                  ///< Classes stored per voxel (SSMI: top 3).
  static constexpr std::uint8_t kNoClass = 255;     ///< Marks an empty slot.

  std::array<float, kSlots> logodds{0.f, 0.f, 0.f}; ///< Class log-odds vs free, strongest first.
  float others = 0.f;                               ///< Log-odds of all unstored classes vs free.
  std::array<std::uint8_t, kSlots> class_id{kNoClass, kNoClass, kNoClass};
  std::uint8_t count = 0;                           ///< Number of used slots (0..3).

  bool operator==(const SemanticState& o) const;
  bool operator!=(const SemanticState& o) const { return !(*this == o); }

  /// Hit with class `c`: psi to c, phi to every other entry; a new class enters at
  /// l_others + psi and, past three, the weakest entry merges into others (log-sum-exp).
  void apply_hit(int c, const UpdateRule& rule);
  /// Pass-through (the voxel was seen free): phi to every entry.
  void apply_free(const UpdateRule& rule);
  /// True when apply_hit(c) would change nothing (saturated on c).
  bool hit_is_noop(int c, const UpdateRule& rule) const;
  /// True when apply_free would change nothing (saturated free).
  bool free_is_noop(const UpdateRule& rule) const;

  /// Occupancy log-odds l_occ = ln(e^others + sum_c e^l_c).
  float occupancy_logodds() const;
  /// Occupancy probability p_occ = 1 / (1 + e^-l_occ).
  double occupancy() const;
  /// Probability of the free category, 1 / (1 + e^l_occ).
  double free_probability() const;
  /// Most likely stored class (slot 0), or -1 when no class is stored.
  int most_likely_class() const { return count > 0 ? class_id[0] : -1; }
  /// Log-odds of the most likely class (slot 0); l_others when none is stored.
  float top_logodds() const { return count > 0 ? logodds[0] : others; }
  /// Log-odds of class c: its slot when stored, else l_others.
  float class_logodds(int c) const;
  /// p(class c) among `num_classes` classes; unstored classes share the others mass equally.
  double class_probability(int c, int num_classes) const;
  /// Shannon entropy (nats) over `categories` for a map of `num_classes` classes.
  double entropy(EntropyCategories categories, int num_classes) const;
  /// Writes {free, class 0..num_classes-1} probabilities into `out` (size num_classes + 1).
  void distribution(int num_classes, double* out) const;
};

static_assert(sizeof(SemanticState) == 20, "SemanticState must stay compact");

/// Entropy (nats) of a never-observed voxel under SSMI's prior chi, u = `unseen_logodds`
/// (-0.1 in SSMI): [0, u x K] for kPaper, [0, u, u, u, u] for kPrototype.
double unseen_entropy(float unseen_logodds, EntropyCategories categories, int num_classes);

/// Shannon entropy (nats) of softmax([0, l_1, ..., l_n]), a log-odds vector relative to free.
double logodds_entropy(const float* l, int n);

}  // namespace canopy::mapping
