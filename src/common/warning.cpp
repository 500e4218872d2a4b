#include "canopy/common/warning.h"

#include <cstdio>
#include <mutex>

namespace canopy {

namespace {

struct Handler {
  std::mutex mutex;
  std::function<void(const std::string&)> handler;
};

Handler& current() {
  static Handler h;
  return h;
}

}  // namespace

void warn(const std::string& line) {
  Handler& h = current();
  std::function<void(const std::string&)> handler;
  {
    std::lock_guard<std::mutex> lock(h.mutex);
    handler = h.handler;
  }
  if (handler) handler(line);
  else std::fprintf(stderr, "canopy: warning: %s\n", line.c_str());
}

std::function<void(const std::string&)> set_warning_handler(std::function<void(const std::string&)> handler) {
  Handler& h = current();
  std::lock_guard<std::mutex> lock(h.mutex);
  std::swap(h.handler, handler);
  return handler;
}

}  // namespace canopy
