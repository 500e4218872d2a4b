#pragma once
// Segmentation noise as in the paper (Experiments): per image and per mask, the true class
// with probability P_gt, else a wrong class. A mask is a 4-connected region of pixels with
// the same class (and the same fruit instance, when instance ids are given); background is
// not a mask. The wrong class is drawn uniformly from the other classes, background
// included: with three classes and P_gt = 0.7 a fruit mask becomes leaf with 0.15 and
// background with 0.15, as in the prototype.

#include <cstdint>

#include "canopy/common/image.h"
#include "canopy/common/random.h"

namespace canopy::perception {

/// Counters of one noisy image.
struct MaskNoiseStats {
  std::size_t masks = 0;    ///< Non-background masks.
  std::size_t flipped = 0;  ///< Masks given a wrong class.
};

/// Uniform double in [0, 1) from a 64-bit generator (same on every platform).

/// Labels masks of `labels` (class indices < num_classes) and returns them as a mask id
/// image (-1 on background); `instance` may be empty. Returns the number of masks.
int label_masks(const Image<std::uint8_t>& labels, const Image<std::int32_t>& instance, Image<std::int32_t>* masks);

/// Applies the noise in place. p_gt = 1 leaves `labels` untouched and draws nothing.
MaskNoiseStats apply_mask_noise(Image<std::uint8_t>& labels, const Image<std::int32_t>& instance, int num_classes,
                                double p_gt, Rng& rng);

}  // namespace canopy::perception
