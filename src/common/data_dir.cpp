#include "canopy/common/data_dir.h"

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "canopy/common/error.h"

namespace fs = std::filesystem;

namespace canopy {

namespace {

bool is_data_dir(const fs::path& dir) {
  std::error_code ec;
  return !dir.empty() && fs::is_regular_file(dir / "configs" / "canopy.yaml", ec);
}

fs::path executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

// The folder of the binary this code is linked into: the executable, or a shared object
// loaded by another program (the Python module inside python3). Found from the file mapped at
// this function's address in /proc/self/maps (absolute; dladdr names the main program by its
// argv[0], which may be relative to another folder).
fs::path code_dir() {
  const auto here = reinterpret_cast<std::uintptr_t>(&executable_dir);
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream in(line);
    if (!(in >> std::hex >> lo >> dash >> hi) || dash != '-' || here < lo || here >= hi) continue;
    const std::size_t slash = line.find('/');
    if (slash == std::string::npos) return {};
    return fs::path(line.substr(slash)).parent_path();
  }
  return {};
}

// The pointer file's first line, resolved against the pointer's folder.
fs::path follow_pointer(const fs::path& dir) {
  std::ifstream in(dir / kDataDirPointer);
  std::string line;
  if (!in || !std::getline(in, line) || line.empty()) return {};
  const fs::path target(line);
  return (target.is_absolute() ? target : dir / target).lexically_normal();
}

std::string find_data_dir() {
  if (const char* env = std::getenv("CANOPY_DATA_DIR"); env && *env) {
    const fs::path p = fs::absolute(env).lexically_normal();
    return is_data_dir(p) ? p.string() : std::string();
  }
  // From the folder of the binary holding this code (the executable, or the Python module in
  // <prefix>/lib/python3/dist-packages/canopy/ or <build>/python/canopy/), then from the
  // executable's: that folder and its parents, for an installed prefix (<parent>/share/canopy)
  // or a build tree's pointer file.
  for (const fs::path& start : {code_dir(), executable_dir()}) {
    if (start.empty()) continue;
    for (fs::path d = start; !d.empty(); d = d.parent_path()) {
      if (d != start) {
        const fs::path installed = (d / "share" / "canopy").lexically_normal();
        if (is_data_dir(installed)) return installed.string();
      }
      const fs::path p = follow_pointer(d);
      if (is_data_dir(p)) return p.string();
      if (d == d.root_path()) break;
    }
  }
  return {};
}

}  // namespace

std::string data_dir() {
  static const std::string dir = find_data_dir();  // the environment and the executable do not change
  return dir;
}

std::string find_data_file(const std::string& relative_path) {
  if (relative_path.empty()) return relative_path;
  if (fs::path(relative_path).is_absolute() || fs::exists(relative_path)) return fs::absolute(relative_path).string();
  const std::string dir = data_dir();
  if (!dir.empty()) {
    const fs::path p = fs::path(dir) / relative_path;
    if (fs::exists(p)) return p.string();
    return relative_path;
  }
  // No data folder: say where canopy looked, naming the variable that chooses it.
  const char* env = std::getenv("CANOPY_DATA_DIR");
  if (env && *env)
    throw InputError("CANOPY_DATA_DIR: '" + std::string(env) +
                     "' is not canopy's data folder (it has no configs/canopy.yaml), so '" + relative_path +
                     "' cannot be found; set it to the folder holding configs/, models/ and worlds/, or unset it");
  throw InputError("'" + relative_path + "' is not in the current folder and canopy's data folder was not found " +
                   (env ? std::string("(CANOPY_DATA_DIR is set but empty)") : std::string("beside the program")) +
                   "; set CANOPY_DATA_DIR to the folder holding configs/, models/ and worlds/");
}

}  // namespace canopy
