"""SIGTERM handled as Ctrl-C (docs/python.md#what-the-module-holds).

canopy's long calls (run_mission, record_bag, export_bag, map_frames, map_bag) stop on Ctrl-C
and keep what the call promises: Python raises KeyboardInterrupt, the call finishes its step,
saves or removes its output and raises KeyboardInterrupt. Python's default for SIGTERM (what
`kill` and SLURM's scancel send) ends the process at once instead: nothing is saved, and an
output folder is left as DIR.partial (the next run on DIR removes it). stop_on_sigterm() makes
SIGTERM take Ctrl-C's path; `python3 -m canopy` calls it first thing.
"""

import signal
import sys

_received = 0


def _interrupt(signum, frame):
    global _received
    _received = signum
    raise KeyboardInterrupt(f"interrupted by {signal.Signals(signum).name}")


def _note(signum, frame):
    global _received
    _received = signum


def note_while_the_command_imports():
    """Run as `python3 -m canopy` (the interpreter's own command line, sys.orig_argv, says so):
    while the package imports (0.4 s: the extension, numpy), SIGINT and SIGTERM are noted, and
    the command ends at its start, nothing done. Imported by a program, canopy leaves its
    signals alone."""
    argv = getattr(sys, "orig_argv", [])
    if "-m" in argv and argv[argv.index("-m") + 1:argv.index("-m") + 2] == ["canopy"]:
        signal.signal(signal.SIGTERM, _note)
        signal.signal(signal.SIGINT, _note)


def received():
    """The signal noted or raised so far (0 when none)."""
    return _received


def stop_on_sigterm():
    """Makes SIGTERM raise KeyboardInterrupt as Ctrl-C (SIGINT) does, and notes which of the two
    arrived (exit_code). Call it from the main thread."""
    signal.signal(signal.SIGTERM, _interrupt)
    signal.signal(signal.SIGINT, _interrupt)


def exit_code():
    """128 + the signal that arrived: 130 for Ctrl-C, 143 for SIGTERM (as the canopy CLI)."""
    return 128 + (_received or signal.SIGINT)
