#!/usr/bin/env python3
"""Tests mirror the sources (docs/development.md): every C++ test file is
tests/<module>/<unit>_test.cpp, or <unit>_<aspect>_test.cpp, for a source unit of that module:
src/<module>/.../<unit>.cpp or include/canopy/<module>/.../<unit>.h. tests/cli tests the command
line tool, whose units are tools/cmd_<command>.cpp; tests/support holds the test main."""
import pathlib
import sys

ROOT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")


def units(module):
    if module == "cli":
        return {p.stem for p in (ROOT / "tools").glob("*.cpp")}
    found = {p.stem for p in (ROOT / "src" / module).rglob("*.cpp")}
    return found | {p.stem for p in (ROOT / "include" / "canopy" / module).rglob("*.h")}


problems = []
tests = sorted(p for p in (ROOT / "tests").rglob("*.cpp") if p.relative_to(ROOT / "tests").parts[0] != "support")
for t in tests:
    module = t.relative_to(ROOT / "tests").parts[0]
    if not t.name.endswith("_test.cpp"):
        problems.append(f"{t.relative_to(ROOT)}: not named <unit>_test.cpp")
        continue
    stem = t.name[: -len("_test.cpp")]
    if not any(stem == u or stem.startswith(u + "_") for u in units(module)):
        problems.append(f"{t.relative_to(ROOT)}: no source unit '{stem}' in module {module}")
for p in problems:
    print(p)
print(f"tests mirror: {len(problems)} problem(s) in {len(tests)} test files")
sys.exit(1 if problems else 0)
