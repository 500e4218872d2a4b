#include "canopy/nbv/nbv_params.h"


namespace canopy::nbv {

std::string to_string(Proximity p) { return enum_name(kProximityNames, p); }

Proximity proximity_from_string(const std::string& s, const std::string& where) {
  return enum_from_name(kProximityNames, s, where, "proximity");
}

}  // namespace canopy::nbv
