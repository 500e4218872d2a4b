#pragma once
// Error conventions (STYLE.md): bad user input throws InputError whose message names the
// file, key and value; broken internal invariants fail CANOPY_CHECK; expected outcomes
// ("no IK solution") are return values, not exceptions.

#include <sstream>
#include <stdexcept>
#include <string>

namespace canopy {

/// Bad user input: a malformed or missing file, an unknown key, an invalid value. The CLI
/// prints the message on one line and exits with code 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

/// The user stopped a run (Ctrl-C, SIGTERM) after its partial results were saved; the CLI
/// exits with 128 + the signal (130, 143).
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted; partial results saved and marked incomplete") {}
  explicit Interrupted(const std::string& what) : std::runtime_error(what) {}
};

/// The system refused a read or write (disk full, a read-only file system, no permission, a
/// path that cannot be made): not a bug and not the run's fault. The CLI prints the message on
/// one line and exits with code 2, like bad input; whatever the command staged is removed.
class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& what) : std::runtime_error(what) {}
};

/// A broken internal invariant (a bug, not bad input).
class InternalError : public std::logic_error {
 public:
  explicit InternalError(const std::string& what) : std::logic_error(what) {}
};

namespace detail {
[[noreturn]] void check_failed(const char* expr, const char* file, int line, const std::string& msg);
}  // namespace detail

}  // namespace canopy

/// Always-on invariant check; throws canopy::InternalError with the location.
#define CANOPY_CHECK(cond, msg)                                                   \
  do {                                                                            \
    if (!(cond)) {                                                                \
      std::ostringstream canopy_check_os_;                                        \
      canopy_check_os_ << msg;                                                    \
      ::canopy::detail::check_failed(#cond, __FILE__, __LINE__, canopy_check_os_.str()); \
    }                                                                             \
  } while (0)
