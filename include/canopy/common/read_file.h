#pragma once
// Reading whole input files with a size limit, refusing folders, devices and pipes.

#include <cstdint>
#include <string>

namespace canopy {

/// Largest file read_file reads whole by default (maps, meshes, CSV ground truth).
constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t(1) << 30;
/// Reads a whole file; throws InputError when it is a folder, not a regular file (a device
/// such as /dev/zero, a pipe), larger than `max_bytes`, or cannot be opened or read.
std::string read_file(const std::string& path, std::uintmax_t max_bytes = kMaxInputFileBytes);

}  // namespace canopy
