#pragma once
// Ctrl-C (SIGINT) and SIGTERM (what `kill` and SLURM's scancel send), handled the same way by
// every command. By default the process ends at once with 128 + the signal (130, 143), as a
// program without handlers would. A command that can save what it has done opens an
// InterruptScope: while one is open a signal only sets a flag, which the command polls, saves
// its partial results (marked incomplete) and exits with the same code.

#include <csignal>

namespace canopy {

/// Installs the SIGINT and SIGTERM handlers and ignores SIGPIPE (output to a closed pipe is
/// never fatal) and SIGXFSZ (a write past `ulimit -f` fails like a full disk); call once,
/// first thing in main().
void install_interrupt_handlers();
/// True once SIGINT or SIGTERM arrived while an InterruptScope was open.
bool interrupt_requested();
/// How many signals arrived while an InterruptScope was open. A step that runs after the
/// command was interrupted (saving the work so far) stops only for a signal later than the
/// count it started with: the first signal ends the work, a second one the saving's extras.
int interrupt_count();
/// The exit code for the signal that arrived: 128 + signal (130 for SIGINT, 143 for SIGTERM).
int interrupt_exit_code();

/// While alive, SIGINT and SIGTERM set the flag instead of ending the process.
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

}  // namespace canopy
