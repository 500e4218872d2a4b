// The schema of canopy's records (schema.h): the report's groups and the tables of fields.

#include "canopy/records/schema.h"

namespace canopy::records {

const char* report_group_title(ReportGroup group) {
  switch (group) {
    case ReportGroup::kDetection: return "Detection and shape";
    case ReportGroup::kCompleteness: return "Completeness and voxel precision";
    case ReportGroup::kMotionCost: return "Motion cost";
    case ReportGroup::kNone: break;
  }
  return "";
}

std::string fields_markdown(const std::vector<FieldInfo>& fields, const std::string& first) {
  std::string s = "| " + first + " | unit | meaning |\n| --- | --- | --- |\n";
  for (const FieldInfo& f : fields) s += "| `" + f.name + "` | " + f.field.unit + " | " + f.field.doc + " |\n";
  return s;
}

}  // namespace canopy::records
