#pragma once
// Warnings for the user from the library: one line each (a setting read under its former
// name). The library does not print; the front end that set a handler routes them to its log
// (the CLI to its spdlog lines); without one they go to stderr as "canopy: warning: <line>".

#include <functional>
#include <string>

namespace canopy {

/// Hands one line to the warning handler.
void warn(const std::string& line);
/// Routes warnings to `handler` from now on (null: back to stderr); returns the previous one.
/// Thread-safe; set once at start-up.
std::function<void(const std::string&)> set_warning_handler(std::function<void(const std::string&)> handler);

}  // namespace canopy
