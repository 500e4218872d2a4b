#include "canopy/perception/segmentation_noise.h"

#include <vector>

#include "canopy/common/error.h"

namespace canopy::perception {

std::string to_string(NoiseModel m) { return enum_name(kNoiseModelNames, m); }

namespace {

// A wrong class for true class c, uniform over the other num_classes - 1 classes.
int wrong_class(int c, int num_classes, double u) {
  int wrong = static_cast<int>(u * (num_classes - 1));  // 0 .. K-2
  if (wrong >= num_classes - 1) wrong = num_classes - 2;
  if (wrong >= c) ++wrong;  // skip the true class
  return wrong;
}

}  // namespace

int label_masks(const Image<std::uint8_t>& labels, const Image<std::int32_t>& instance, Image<std::int32_t>* masks) {
  const int w = labels.width, h = labels.height;
  const bool use_instance = !instance.empty();
  CANOPY_CHECK(!use_instance || (instance.width == w && instance.height == h), "instance image size differs");
  *masks = Image<std::int32_t>(w, h, -1);
  auto same = [&](std::size_t a, std::size_t b) {
    return labels.data[a] == labels.data[b] && (!use_instance || instance.data[a] == instance.data[b]);
  };
  int next = 0;
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < labels.data.size(); ++seed) {
    if (labels.data[seed] == 0 || masks->data[seed] >= 0) continue;
    const int id = next++;
    masks->data[seed] = id;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::size_t p = stack.back();
      stack.pop_back();
      const int x = int(p % std::size_t(w)), y = int(p / std::size_t(w));
      const std::size_t nb[4] = {p - 1, p + 1, p - std::size_t(w), p + std::size_t(w)};
      const bool ok[4] = {x > 0, x + 1 < w, y > 0, y + 1 < h};
      for (int k = 0; k < 4; ++k) {
        if (!ok[k] || masks->data[nb[k]] >= 0 || !same(p, nb[k])) continue;
        masks->data[nb[k]] = id;
        stack.push_back(nb[k]);
      }
    }
  }
  return next;
}

MaskNoiseStats apply_mask_noise(Image<std::uint8_t>& labels, const Image<std::int32_t>& instance, int num_classes,
                                double p_gt, Rng& rng) {
  MaskNoiseStats stats;
  if (p_gt >= 1.0 || num_classes < 2) return stats;
  Image<std::int32_t> masks;
  const int n = label_masks(labels, instance, &masks);
  stats.masks = static_cast<std::size_t>(n);
  // One draw per mask, in mask order (row-major order of each mask's first pixel).
  std::vector<int> new_class(static_cast<std::size_t>(n), -1);
  std::vector<int> true_class(static_cast<std::size_t>(n), -1);
  for (std::size_t i = 0; i < labels.data.size(); ++i) {
    const int m = masks.data[i];
    if (m >= 0 && true_class[static_cast<std::size_t>(m)] < 0) true_class[static_cast<std::size_t>(m)] = labels.data[i];
  }
  for (int m = 0; m < n; ++m) {
    const int c = true_class[static_cast<std::size_t>(m)];
    if (c >= num_classes) {  // not a class: left for the extractor to count and skip
      new_class[static_cast<std::size_t>(m)] = c;
      --stats.masks;
      continue;
    }
    if (rng.uniform() < p_gt) {
      new_class[static_cast<std::size_t>(m)] = c;
      continue;
    }
    new_class[static_cast<std::size_t>(m)] = wrong_class(c, num_classes, rng.uniform());
    ++stats.flipped;
  }
  for (std::size_t i = 0; i < labels.data.size(); ++i) {
    const int m = masks.data[i];
    if (m >= 0) labels.data[i] = static_cast<std::uint8_t>(new_class[static_cast<std::size_t>(m)]);
  }
  return stats;
}

MaskNoiseStats apply_class_mask_noise(Image<std::uint8_t>& labels, int num_classes, double p_gt, Rng& rng) {
  MaskNoiseStats stats;
  if (p_gt >= 1.0 || num_classes < 2) return stats;
  std::vector<bool> present(static_cast<std::size_t>(num_classes), false);
  for (const std::uint8_t l : labels.data)
    if (l < num_classes) present[l] = true;
  // map[c] = the class every pixel of class c becomes in this image.
  std::vector<std::uint8_t> map(256);
  for (int c = 0; c < 256; ++c) map[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(c);
  for (int c = 1; c < num_classes; ++c) {
    const double keep = rng.uniform(), which = rng.uniform();  // both drawn for every class
    if (!present[static_cast<std::size_t>(c)]) continue;
    ++stats.masks;
    if (keep < p_gt) continue;
    map[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(wrong_class(c, num_classes, which));
    ++stats.flipped;
  }
  if (stats.flipped == 0) return stats;
  for (std::uint8_t& l : labels.data) l = map[l];
  return stats;
}

MaskNoiseStats apply_segmentation_noise(NoiseModel model, Image<std::uint8_t>& labels,
                                        const Image<std::int32_t>& instance, int num_classes, double p_gt, Rng& rng) {
  return model == NoiseModel::kPerClassMask ? apply_class_mask_noise(labels, num_classes, p_gt, rng)
                                            : apply_mask_noise(labels, instance, num_classes, p_gt, rng);
}

}  // namespace canopy::perception
