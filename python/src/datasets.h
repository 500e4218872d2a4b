#pragma once
// The recorded-data rules of datasets/ in Python (datasets.cpp), for the bag reader
// (canopy/bag/read.py): label colours decoded by ClassColorTable::decode, stamps paired by
// nearest_timestamp, so a bag and a frame folder follow one rule each.

#include "convert.h"

namespace canopy::python {

/// canopy.decode_class_colors, canopy.nearest_stamps.
void bind_datasets(py::module_& m);

}  // namespace canopy::python
