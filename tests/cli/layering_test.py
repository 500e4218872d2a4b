#!/usr/bin/env python3
"""The house's rules, checked on the source tree (docs/architecture.md):
 - a module includes only the modules below it on the data path (the table below);
 - the planning libraries (mapping, nbv, motion) never include world/ (the ground truth) or
   MuJoCo, and only sim/ includes MuJoCo or OSMesa headers;
 - each module's CMake target names every canopy module it includes (no module compiles only
   because the include folder is shared).
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
ALLOWED = {
    "common": set(),
    "ros2": {"common"},
    "robot": {"common"},
    "world": {"common", "robot"},
    "sim": {"common", "robot", "world"},
    "perception": {"common"},
    "mapping": {"common", "perception"},
    "datasets": {"common", "perception", "mapping"},
    "evaluation": {"common", "perception", "mapping", "world"},
    "nbv": {"common", "perception", "mapping"},
    "motion": {"common", "robot", "perception", "mapping", "nbv"},
    "settings": {"common", "robot", "perception", "mapping", "evaluation", "nbv", "motion"},
    "records": {"common", "robot", "world", "perception", "mapping", "evaluation", "nbv", "motion", "settings"},
    "video": {"common", "robot", "world", "sim", "perception", "mapping"},
    "mission": {"common", "robot", "world", "sim", "perception", "mapping", "datasets", "evaluation", "nbv",
                "motion", "settings", "records"},
    "experiments": {"common", "robot", "world", "sim", "perception", "mapping", "evaluation", "nbv", "motion",
                    "settings", "records", "mission"},
    "jobs": {"common", "robot", "world", "sim", "perception", "mapping", "datasets", "evaluation", "nbv", "motion",
             "settings", "records", "video", "mission", "experiments"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]([^>"]+)[>"]', re.M)
problems = []
for module, allowed in ALLOWED.items():
    files = list((ROOT / "include" / "canopy" / module).rglob("*.h")) + list((ROOT / "src" / module).rglob("*.[ch]*"))
    if not files:
        problems.append(f"{module}: no files found")
        continue
    used = set()
    for f in files:
        if f.suffix not in (".h", ".cpp"):
            continue
        for inc in INCLUDE.findall(f.read_text()):
            m = re.match(r"canopy/([a-z_]+)/", inc)
            if m:
                other = m.group(1)
                if other != module:
                    used.add(other)
                    if other not in allowed:
                        problems.append(f"{f.relative_to(ROOT)}: {module} may not include {inc}")
            if module != "sim" and (inc.startswith("mujoco") or inc.startswith("GL/osmesa")):
                problems.append(f"{f.relative_to(ROOT)}: only sim/ includes MuJoCo or OSMesa ({inc})")
    cmake = (ROOT / "src" / module / "CMakeLists.txt").read_text()
    linked = set(re.findall(r"\bcanopy_([a-z_]+)\b", cmake)) - {module, "warnings", "ompl"}
    for other in sorted(used - {"common"}):
        if other not in linked:
            problems.append(f"src/{module}/CMakeLists.txt: includes {other}/ but does not link canopy_{other}")
for p in problems:
    print(p)
print(f"layering: {len(problems)} problem(s) in {len(ALLOWED)} modules")
sys.exit(1 if problems else 0)
