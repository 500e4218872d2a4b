#pragma once
// Atomic file writing: a file is written to a temporary name in its folder, then renamed into
// place, so a reader (or an interrupted run) never sees half a file.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace canopy {

/// Writes `content` to `path` atomically (temporary file in the same folder, then rename).
/// Throws IoError naming the file and the system's reason (disk full, read-only, ...).
void write_file_atomic(const std::string& path, const std::string& content);
/// Writes pretty-printed JSON atomically.
void write_json_atomic(const std::string& path, const nlohmann::json& j);

/// A temporary name beside `path`, unique per process and per call, so concurrent writers
/// never share a temporary file.
std::string unique_temp_path(const std::string& path);
/// Renames a file or folder; throws IoError carrying the system's reason.
void move_path(const std::string& from, const std::string& to);
/// Moves a finished temporary file into place; removes the temporary file when that fails.
void move_temp_into_place(const std::string& tmp, const std::string& path);

/// Removes a file or folder tree, read-only folders inside it too (the owner's write
/// permission is added first). Returns false when something could not be removed.
bool remove_tree(const std::string& path);

/// One line for a std::filesystem error: the path and the system's reason, without the
/// library's "filesystem error: ..." framing and temporary names in brackets.
std::string describe_filesystem_error(const std::filesystem::filesystem_error& e);

}  // namespace canopy
