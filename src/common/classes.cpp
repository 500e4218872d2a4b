#include "canopy/common/classes.h"

#include <set>

#include "canopy/common/error.h"

namespace canopy {

int SemanticClasses::index_of(const std::string& name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

int SemanticClasses::target_index() const {
  const int i = index_of(target);
  CANOPY_CHECK(i >= 0, "target class '" << target << "' not in the class list");
  return i;
}

Rgb8 SemanticClasses::color(int index) const {
  if (index >= 0 && index < size()) {
    const std::string& n = names[static_cast<size_t>(index)];
    if (n == "background") return {0, 0, 0};
    if (n == "leaf") return {40, 170, 40};
    if (n == "fruit") return {220, 30, 30};
  }
  static const Rgb8 palette[] = {{30, 90, 220}, {230, 200, 20}, {200, 40, 200}, {20, 200, 200},
                                 {240, 130, 20}, {120, 120, 120}, {150, 80, 30}, {255, 255, 255}};
  return palette[static_cast<unsigned>(index) % 8];
}

void SemanticClasses::validate(const std::string& where) const {
  if (names.empty() || names.front() != "background")
    throw InputError(where + ": key 'classes': the class list must start with 'background'");
  if (names.size() > static_cast<size_t>(kMaxClasses))
    throw InputError(where + ": key 'classes': " + std::to_string(names.size()) + " classes, at most " +
                     std::to_string(kMaxClasses) + " are supported");
  std::set<std::string> seen;
  for (const auto& n : names) {
    if (n.empty()) throw InputError(where + ": key 'classes': empty class name");
    if (!seen.insert(n).second) throw InputError(where + ": key 'classes': value '" + n + "' is listed twice");
  }
  if (index_of(target) < 0)
    throw InputError(where + ": key 'target_class': value '" + target + "' is not in the class list");
}

}  // namespace canopy
