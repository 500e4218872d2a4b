#include "canopy/mapping/semantic_state.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "canopy/common/classes.h"
#include "canopy/common/error.h"

namespace canopy::mapping {

namespace {

inline float clampf(float v, const UpdateRule& r) { return v < r.min ? r.min : (v > r.max ? r.max : v); }

// Keeps slots sorted strongest first; equal log-odds order by class id (a canonical form, so
// equal beliefs compare equal and prune).
void sort_slots(SemanticState& s) {
  for (int i = 1; i < s.count; ++i) {
    for (int j = i; j > 0; --j) {
      const bool swap = s.logodds[j] > s.logodds[j - 1] ||
                        (s.logodds[j] == s.logodds[j - 1] && s.class_id[j] < s.class_id[j - 1]);
      if (!swap) break;
      std::swap(s.logodds[j], s.logodds[j - 1]);
      std::swap(s.class_id[j], s.class_id[j - 1]);
    }
  }
}

// ln(e^a + e^b) without overflow.
inline float log_sum_exp(float a, float b) {
  const float m = std::max(a, b);
  return m + std::log(std::exp(a - m) + std::exp(b - m));
}

}  // namespace

bool SemanticState::operator==(const SemanticState& o) const {
  return count == o.count && others == o.others && logodds == o.logodds && class_id == o.class_id;
}

void SemanticState::apply_hit(int c, const UpdateRule& rule) {
  int found = -1;
  for (int i = 0; i < count; ++i) {
    if (class_id[i] == c) {
      found = i;
      logodds[i] = clampf(logodds[i] + rule.hit, rule);
    } else {
      logodds[i] = clampf(logodds[i] + rule.pass, rule);
    }
  }
  if (found < 0) {
    const float entering = clampf(others + rule.hit, rule);
    others = others + rule.pass;
    if (count < kSlots) {
      logodds[count] = entering;
      class_id[count] = static_cast<std::uint8_t>(c);
      ++count;
    } else {
      // Four candidates: the three stored plus the newcomer; the weakest joins others.
      int weakest = kSlots - 1;  // slots are sorted, so the last is the weakest stored one
      if (entering < logodds[weakest] ||
          (entering == logodds[weakest] && c > class_id[weakest])) {
        others = log_sum_exp(others, entering);
      } else {
        others = log_sum_exp(others, logodds[weakest]);
        logodds[weakest] = entering;
        class_id[weakest] = static_cast<std::uint8_t>(c);
      }
    }
    others = clampf(others, rule);
  } else {
    others = clampf(others + rule.pass, rule);
  }
  sort_slots(*this);
}

void SemanticState::apply_free(const UpdateRule& rule) {
  for (int i = 0; i < count; ++i) logodds[i] = clampf(logodds[i] + rule.pass, rule);
  others = clampf(others + rule.pass, rule);
  sort_slots(*this);  // clamping can create ties
}

bool SemanticState::hit_is_noop(int c, const UpdateRule& rule) const {
  if (count == 0 || class_id[0] != c || logodds[0] < rule.max || others > rule.min) return false;
  for (int i = 1; i < count; ++i)
    if (logodds[i] > rule.min) return false;
  return true;
}

bool SemanticState::free_is_noop(const UpdateRule& rule) const {
  if (others > rule.min) return false;
  for (int i = 0; i < count; ++i)
    if (logodds[i] > rule.min) return false;
  return true;
}

float SemanticState::occupancy_logodds() const {
  float m = others;
  for (int i = 0; i < count; ++i) m = std::max(m, logodds[i]);
  float sum = std::exp(others - m);
  for (int i = 0; i < count; ++i) sum += std::exp(logodds[i] - m);
  return m + std::log(sum);
}

double SemanticState::occupancy() const { return 1.0 / (1.0 + std::exp(-double(occupancy_logodds()))); }

double SemanticState::free_probability() const { return 1.0 / (1.0 + std::exp(double(occupancy_logodds()))); }

float SemanticState::class_logodds(int c) const {
  for (int i = 0; i < count; ++i)
    if (class_id[i] == c) return logodds[i];
  return others;
}

double SemanticState::class_probability(int c, int num_classes) const {
  const double z = 1.0 + std::exp(double(occupancy_logodds()));
  for (int i = 0; i < count; ++i)
    if (class_id[i] == c) return std::exp(double(logodds[i])) / z;
  const int unstored = num_classes - count;
  if (c < 0 || c >= num_classes || unstored <= 0) return 0.0;
  return std::exp(double(others)) / z / unstored;
}

void SemanticState::distribution(int num_classes, double* out) const {
  out[0] = free_probability();
  for (int c = 0; c < num_classes; ++c) out[c + 1] = class_probability(c, num_classes);
}

double SemanticState::entropy(EntropyCategories categories, int num_classes) const {
  float l[SemanticClasses::kMaxClasses + 1];
  int n = 0;
  for (int i = 0; i < count; ++i) l[n++] = logodds[i];
  if (categories == EntropyCategories::kPrototype) {
    while (n < kSlots) l[n++] = others;  // empty slots hold l_others
    l[n++] = others;
  } else {
    const int unstored = num_classes - count;
    const float share = unstored > 0 ? others - float(std::log(double(unstored))) : 0.f;
    for (int i = 0; i < unstored; ++i) l[n++] = share;
  }
  return logodds_entropy(l, n);
}

double logodds_entropy(const float* l, int n) {
  // softmax over [0, l_1..l_n]; H = ln Z - sum p_i x_i with x_0 = 0.
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = std::max(m, double(l[i]));
  double z = std::exp(-m), zx = 0.0;
  for (int i = 0; i < n; ++i) {
    const double e = std::exp(double(l[i]) - m);
    z += e;
    zx += e * double(l[i]);
  }
  return m + std::log(z) - zx / z;
}

double unseen_entropy(float unseen_logodds, EntropyCategories categories, int num_classes) {
  float l[SemanticClasses::kMaxClasses + 1];
  const int n = categories == EntropyCategories::kPrototype ? SemanticState::kSlots + 1 : num_classes;
  for (int i = 0; i < n; ++i) l[i] = unseen_logodds;
  return logodds_entropy(l, n);
}

std::string to_string(EntropyCategories c) { return enum_name(kEntropyCategoriesNames, c); }

}  // namespace canopy::mapping
