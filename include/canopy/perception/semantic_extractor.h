#pragma once
// The semantic extractor (paper Methods (i)): labels a frame's pixels by colour segmentation
// or with the renderer's true labels, adds segmentation noise (P_gt) and optional depth
// noise, and turns depth + labels into a labelled point cloud in the world frame.

#include <cstdint>
#include <string>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"
#include "canopy/common/random.h"
#include "canopy/common/params.h"
#include "canopy/perception/color_segmentation.h"
#include "canopy/perception/labelled_cloud.h"
#include "canopy/perception/segmentation_noise.h"

namespace canopy::perception {

/// Where pixel labels come from.
enum class LabelSource { kColor, kTruth };
inline constexpr EnumName<LabelSource> kLabelSourceNames[] = {{LabelSource::kColor, "color"},
                                                              {LabelSource::kTruth, "truth"}};

/// "color" or "truth".
std::string to_string(LabelSource s);
/// Parses "color" / "truth"; throws InputError naming `where` otherwise.
LabelSource label_source_from_string(const std::string& s, const std::string& where);

/// What becomes of pixels without a depth return (depth 0, NaN or inf: nothing within the
/// camera's range, or the robot's own pixels removed by the renderer's self filter).
enum class MissingDepth { kSkip, kCarve };
inline constexpr EnumName<MissingDepth> kMissingDepthNames[] = {{MissingDepth::kSkip, "skip"},
                                                                {MissingDepth::kCarve, "carve"}};

/// Extractor settings; defaults are the paper's (colour segmentation, P_gt = 0.7 per class mask,
/// missing depth carved as the released code does).
struct ExtractorParams {
  LabelSource source = LabelSource::kColor;
  ColorSegmentationParams color;
  double p_gt = 0.7;
  NoiseModel noise = NoiseModel::kPerClassMask;
  double depth_noise_k = 0.0;
  MissingDepth missing_depth = MissingDepth::kCarve;
  double missing_depth_m = 3.0;
  std::uint64_t seed = 1;

  template <class A>
  void visit(A& a) {
    a.choice("source", source, kLabelSourceNames, "Pixel labels: colour segmentation or the renderer's true labels");
    a.section("color", color, "Colour segmentation");
    a("p_gt", p_gt, limits::in(0.0, 1.0), "P_gt: probability a mask keeps its class; 1 = no noise");
    a.choice("noise", noise, kNoiseModelNames, "What one P_gt draw flips (segmentation_noise.h)");
    a("depth_noise_k", depth_noise_k, limits::non_negative(), "Extra depth noise sigma = k z^2 [m]; 0 = none");
    a.choice("missing_depth", missing_depth, kMissingDepthNames,
             "Pixels without depth: carve (a point at missing_depth_m, beyond the map's max range: its ray "
             "carves free space to the ray range, as the released code) or skip");
    a("missing_depth_m", missing_depth_m, limits::in(0.01, 100.0),
      "Depth given to pixels without a return by missing_depth: carve [m]");
    a("seed", seed, limits::non_negative(), "Seed of the label and depth noise (missions derive it from theirs)");
  }
  bool operator==(const ExtractorParams& o) const { return same_params(*this, o); }
};

/// Turns frames into labelled clouds. Holds the noise generator: the n-th frame's noise
/// depends only on the seed and n.
class SemanticExtractor {
 public:
  SemanticExtractor(const ExtractorParams& params, const SemanticClasses& classes);

  /// Pixel labels for `frame` after segmentation and noise (stats->masks*, bad_label).
  Image<std::uint8_t> label(const LabelledFrame& frame, ExtractStats* stats);
  /// The labelled cloud of `frame` (world frame, origin = camera position). With `labels_out`,
  /// also the pixel labels the cloud was made of (label()'s; the same draws of the noise).
  LabelledCloud extract(const LabelledFrame& frame, Image<std::uint8_t>* labels_out = nullptr);

  const ExtractorParams& params() const { return params_; }
  /// The noise generator's state. A caller that discards a cloud puts the state from before it
  /// back, and the next frame is noised as if the discarded one had never been extracted.
  Rng noise_state() const { return rng_; }
  void set_noise_state(const Rng& state) { rng_ = state; }

 private:
  ExtractorParams params_;
  SemanticClasses classes_;
  Rng rng_;
};

/// Unprojects valid pixels of `depth_m` with `labels` into the world frame: the cloud part of
/// the extractor, without noise. Skips and counts labels >= num_classes and negative depths;
/// pixels without a return (depth 0, NaN or +-inf) are skipped and counted (bad_depth) when
/// `missing_depth_m` is 0, else unprojected at that depth with label 0 (background) and
/// counted (missing_depth).
LabelledCloud depth_to_cloud(const CameraIntrinsics& K, const Pose& T_world_camera, const Image<float>& depth_m,
                             const Image<std::uint8_t>& labels, int num_classes, double missing_depth_m = 0.0);

}  // namespace canopy::perception
