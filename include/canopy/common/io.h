#pragma once
// Umbrella header for canopy's file input and output; include the specific header instead
// where one concept is used.

#include "canopy/common/atomic_file.h"  // write_file_atomic, write_json_atomic
#include "canopy/common/output_dir.h"   // StagedDir, output markers
#include "canopy/common/png_io.h"       // PNG images
#include "canopy/common/read_file.h"    // read_file with a size limit
#include "canopy/common/value_text.h"   // format_number, parse_*, pose JSON
