#include "canopy/common/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <cstring>

namespace canopy {

namespace {

std::atomic<int> g_signal{0};
std::atomic<int> g_count{0};
std::atomic<int> g_scopes{0};

extern "C" void on_interrupt(int sig) {
  if (g_scopes.load() > 0) {
    g_signal.store(sig);
    g_count.fetch_add(1);
    return;
  }
  // Nothing to save: end now, as the default action would, with one line (async-signal-safe).
  const char* msg = sig == SIGTERM ? "canopy: terminated\n" : "canopy: interrupted\n";
  const ssize_t ignored = ::write(STDERR_FILENO, msg, std::strlen(msg));
  (void)ignored;
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  // Progress and log lines are never fatal: with stderr piped into `head`, a write after the
  // reader has gone fails with EPIPE instead of killing the run with SIGPIPE (exit 141).
  // (Child processes start with the default action again: see process.cpp.)
  struct sigaction ignore;
  std::memset(&ignore, 0, sizeof ignore);
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, nullptr);
  // Likewise a file-size limit (ulimit -f): a write past it fails with EFBIG, reported as one
  // line with exit code 2, instead of killing the process mid-commit.
  sigaction(SIGXFSZ, &ignore, nullptr);
}

bool interrupt_requested() { return g_signal.load() != 0; }
int interrupt_count() { return g_count.load(); }
int interrupt_exit_code() { return 128 + (g_signal.load() ? g_signal.load() : SIGINT); }

InterruptScope::InterruptScope() { ++g_scopes; }
InterruptScope::~InterruptScope() { --g_scopes; }

}  // namespace canopy
