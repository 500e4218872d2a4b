#pragma once
// The records' schema in Python (records.cpp): views as a dict of arrays, one view as a dict,
// both by the schema's names (records::ViewRecord::visit).

#include <string>
#include <vector>

#include "canopy/records/records.h"
#include "convert.h"

namespace canopy::python {

/// One array per field of the views' schema (every column of views.csv, then goal_pose and
/// reached_pose (N, 4, 4), target (N, 3), message, ...): empty fields as NaN.
py::dict views_dict(const std::vector<records::ViewRecord>& views, const std::string& method);
/// One view's fields known when it is taken (all but its map figures, which come one view later).
py::dict view_dict(const records::ViewRecord& view, const std::string& method);
/// canopy.vocabulary, canopy.view_fields, canopy.summary_fields.
void bind_records(py::module_& m);

}  // namespace canopy::python
