#pragma once
// Where canopy's shipped data (models/, worlds/, configs/, plot scripts) lives at run time.
// Nothing is baked in as an absolute path: the folder is found, in this order, from
//  1. the CANOPY_DATA_DIR environment variable;
//  2. the binary holding canopy's code (the executable, or the Python module loaded by
//     python3), then the running executable: walking up from its folder, either an installed
//     prefix `<parent>/share/canopy` (`<exe>/../share/canopy`; the module's
//     `<prefix>/lib/python3/dist-packages/canopy/` finds `<prefix>/share/canopy`) or a build
//     tree's `canopy-data-dir` pointer file, holding the source tree's path relative to the
//     pointer's folder.

#include <string>

namespace canopy {

/// Name of the pointer file a build tree writes beside its executables.
constexpr const char* kDataDirPointer = "canopy-data-dir";

/// The data folder (absolute), or "" when none of the places above has one. A folder counts
/// when it holds configs/canopy.yaml.
std::string data_dir();

/// Absolute path of a shipped file given relative to the data folder ("worlds/default.yaml"):
/// an absolute path or one that exists relative to the current directory is taken as is;
/// otherwise the file in data_dir(). Returns `relative_path` unchanged when neither exists
/// (the caller's open then fails naming it). Throws InputError naming CANOPY_DATA_DIR when no
/// data folder was found (the variable names no data folder, is empty, or is unset and none
/// is beside the program).
std::string find_data_file(const std::string& relative_path);

}  // namespace canopy
