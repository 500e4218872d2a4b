#include "canopy/common/read_file.h"

#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"

namespace fs = std::filesystem;

namespace canopy {

std::string read_file(const std::string& path, std::uintmax_t max_bytes) {
  std::error_code ec;
  // A folder opens as an empty stream on Linux: it must not read as an empty file.
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a folder, not a file");
  if (!fs::exists(path, ec)) throw InputError(path + ": cannot open file (it does not exist)");
  // Devices and pipes have no size and may never end (/dev/zero).
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": is not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size (" + ec.message() + ")");
  if (size > max_bytes)
    throw InputError(path + ": is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                     " this input may have");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::string out(static_cast<std::size_t>(size), '\0');
  in.read(out.data(), static_cast<std::streamsize>(size));
  if (in.bad() || in.gcount() != static_cast<std::streamsize>(size)) throw InputError(path + ": cannot read file");
  return out;
}

}  // namespace canopy
