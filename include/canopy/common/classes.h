#pragma once
// The list of semantic classes. Index 0 is always the background; the target class (the
// one the planner maps actively, "fruit" by default) is named in the config.

#include <string>
#include <vector>

#include "canopy/common/image.h"

namespace canopy {

/// Semantic class names, the target class and the colours used to draw label images.
struct SemanticClasses {
  /// Most classes a world may have (the planner's per-voxel tables are fixed-size).
  static constexpr int kMaxClasses = 7;

  std::vector<std::string> names = {"background", "leaf", "fruit"};
  std::string target = "fruit";

  int size() const { return static_cast<int>(names.size()); }
  /// Index of `name`, or -1 when it is not in the list.
  int index_of(const std::string& name) const;
  /// Index of the target class.
  int target_index() const;
  /// Drawing colour of class `index` (background black, leaf green, fruit red, then a palette).
  Rgb8 color(int index) const;
  /// Throws InputError naming `where` when the list is empty, has duplicates, does not start
  /// with "background", has more than kMaxClasses entries or lacks the target.
  void validate(const std::string& where) const;
};

}  // namespace canopy
