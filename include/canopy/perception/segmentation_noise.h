#pragma once
// Segmentation noise (paper Experiments; docs/background/evaluation.md): per image and per mask, the
// true class with probability P_gt, else a wrong class drawn uniformly from the other
// classes, background included (three classes, P_gt = 0.7: a fruit mask becomes leaf with
// 0.15 and background with 0.15, as in the released code). What a "mask" is, is the model:
//  - per_class_mask (the paper's and its code's): all pixels of one class in one image are
//    one mask, so every fruit pixel of an image flips together. One keep draw and one
//    wrong-class draw per non-background class per image, whether the class is present or
//    not, so the noise of image n depends only on the seed and n.
//  - per_region (canopy's first model, far milder): a mask is a 4-connected region of pixels
//    with the same class (and the same fruit instance, when instance ids are given).
// Background is never a mask.

#include <cstdint>
#include <string>

#include "canopy/common/enum_names.h"
#include "canopy/common/image.h"
#include "canopy/common/random.h"

namespace canopy::perception {

/// Counters of one noisy image.
struct MaskNoiseStats {
  std::size_t masks = 0;    ///< Non-background masks.
  std::size_t flipped = 0;  ///< Masks given a wrong class.
};

/// What one noise draw applies to.
enum class NoiseModel { kPerClassMask, kPerRegion };
inline constexpr EnumName<NoiseModel> kNoiseModelNames[] = {{NoiseModel::kPerClassMask, "per_class_mask"},
                                                            {NoiseModel::kPerRegion, "per_region"}};

/// "per_class_mask" / "per_region".
std::string to_string(NoiseModel m);

/// Labels masks of `labels` (class indices < num_classes) and returns them as a mask id
/// image (-1 on background); `instance` may be empty. Returns the number of masks.
int label_masks(const Image<std::uint8_t>& labels, const Image<std::int32_t>& instance, Image<std::int32_t>* masks);

/// per_region noise in place. p_gt = 1 leaves `labels` untouched and draws nothing.
MaskNoiseStats apply_mask_noise(Image<std::uint8_t>& labels, const Image<std::int32_t>& instance, int num_classes,
                                double p_gt, Rng& rng);

/// per_class_mask noise in place: classes 1..num_classes-1 present in `labels` are the masks
/// (labels >= num_classes are left alone). p_gt = 1 leaves `labels` untouched and draws nothing.
MaskNoiseStats apply_class_mask_noise(Image<std::uint8_t>& labels, int num_classes, double p_gt, Rng& rng);

/// The noise of `model` (`instance` is used by per_region only).
MaskNoiseStats apply_segmentation_noise(NoiseModel model, Image<std::uint8_t>& labels,
                                        const Image<std::int32_t>& instance, int num_classes, double p_gt, Rng& rng);

}  // namespace canopy::perception
