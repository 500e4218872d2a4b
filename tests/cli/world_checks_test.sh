#!/usr/bin/env bash
# The command line and Python run the same world checks (the world job,
# canopy/jobs/world_job.h): a world with an imported plant whose ripe-fruit material is leaf
# green, which colour segmentation cannot see, is refused under colour labels by
# `canopy world`, `canopy mission` and Python's canopy.World with the same message, and
# accepted by all three under true labels. A world whose aisle is narrower than the robot's
# base is refused by both with the same message.
# Usage: world_checks_test.sh canopy PYTHON PYTHONPATH
set -u
canopy="$1"
python="$2"
export PYTHONPATH="$3"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# A stem, a leaf and two fruit cubes (OBJ + MTL, metres, +z up); the ripe fruit material
# Pepper_frt1 (capsicum preset: ripe fruit) is as green as the leaf.
"$python" - "$tmp" <<'PY'
import sys
tmp = sys.argv[1]
def box(lo, hi):
    v = [(hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2]) for i in range(8)]
    return v, [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
groups = [("Pepper_brn", (0.24, 0.59, 0.2), [box((-0.01, -0.01, 0), (0.01, 0.01, 1.0))]),
          ("Pepper_lef", (0.16, 0.67, 0.18), [box((0.01, -0.05, 0.8), (0.25, 0.05, 0.805))]),
          ("Pepper_frt1", (0.2, 0.62, 0.15), [box((0.03, -0.04, 0.46), (0.11, 0.04, 0.54)),
                                               box((-0.11, -0.04, 0.61), (-0.03, 0.04, 0.69))])]
obj, mtl, n = ["mtllib plant.mtl"], [], 0
for name, rgb, boxes in groups:
    mtl += [f"newmtl {name}", "Kd %g %g %g" % rgb]
    obj.append(f"usemtl {name}")
    for v, quads in boxes:
        obj += ["v %g %g %g" % p for p in v]
        obj += ["f " + " ".join(str(n + 1 + i) for i in q) for q in quads]
        n += 8
open(f"{tmp}/plant.obj", "w").write("\n".join(obj) + "\n")
open(f"{tmp}/plant.mtl", "w").write("\n".join(mtl) + "\n")
PY
"$canopy" import-plant "$tmp/plant.obj" --preset capsicum --out "$tmp/plants/green" >"$tmp/import.log" 2>&1 ||
  fail "import-plant: $(tail -3 "$tmp/import.log")"
cat >"$tmp/green.yaml" <<EOF2
name: green
seed: 3
rows: {rows: 1, plants_per_row: 1, position_jitter_m: 0.0}
plants:
  - {plant: {import: $tmp/plants/green}, slot: [0, 0]}
EOF2
cat >"$tmp/narrow.yaml" <<EOF2
name: narrow
rows: {row_offset_m: 0.3}
EOF2

# cli_message COMMAND ARGS...: the one-line message of a refused command (exit 2), without "canopy: error: ".
cli_message() {
  local msg code
  msg=$("$canopy" "$@" 2>&1 >/dev/null)
  code=$?
  [[ $code -eq 2 ]] || fail "canopy $*: exit $code (want 2): $msg"
  [[ $(printf '%s\n' "$msg" | grep -c '^canopy: error: ') -eq 1 ]] || fail "canopy $*: not one error line: $msg"
  printf '%s\n' "$msg" | grep '^canopy: error: ' | sed 's/^canopy: error: //'
}
# py_message WORLD SEG: ValueError's message of canopy.World(WORLD) under labels SEG ("" when it loads).
py_message() {
  py_run "$@" | grep '^refused: ' | sed 's/^refused: //'
}
py_run() {
  "$python" - "$1" "$2" <<'PY' 2>"$tmp/py.err"
import sys
import canopy
settings = canopy.Settings().set("mapping.extractor.source", sys.argv[2])
try:
    canopy.World(sys.argv[1], settings=settings)
except ValueError as e:
    print("refused:", e)
PY
}

colour_world=$(cli_message world --world "$tmp/green.yaml" --seg color --out "$tmp/w1")
colour_mission=$(cli_message mission --world "$tmp/green.yaml" --seg color --out "$tmp/m1" --no-plots)
colour_python=$(py_message "$tmp/green.yaml" color)
[[ "$colour_world" == *"plants/green: material 'Pepper_frt1'"*"(labels: color;"* ]] ||
  fail "canopy world's message names no plant and material: $colour_world"
[[ "$colour_mission" == "$colour_world" ]] || fail "canopy mission and canopy world differ: '$colour_mission' vs '$colour_world'"
[[ "$colour_python" == "$colour_world" ]] || fail "Python and canopy world differ: '$colour_python' vs '$colour_world' ($(cat "$tmp/py.err"))"
[[ ! -e "$tmp/w1" && ! -e "$tmp/m1" ]] || fail "a refused command left a folder"

"$canopy" world --world "$tmp/green.yaml" --seg truth --out "$tmp/w2" >"$tmp/w2.log" 2>&1 ||
  fail "canopy world --seg truth refused the green plant: $(tail -2 "$tmp/w2.log")"
truth_python=$(py_message "$tmp/green.yaml" truth)
[[ -z "$truth_python" ]] || fail "Python refused the green plant under truth labels: $truth_python"

aisle_world=$(cli_message world --world "$tmp/narrow.yaml" --out "$tmp/w3")
aisle_python=$(py_message "$tmp/narrow.yaml" color)
[[ "$aisle_world" == *"key 'rows.row_offset_m'"* ]] || fail "canopy world's aisle message: $aisle_world"
[[ "$aisle_python" == "$aisle_world" ]] || fail "Python and canopy world differ on the aisle: '$aisle_python' vs '$aisle_world'"

if ((failures > 0)); then
  echo "$failures failure(s)"
  exit 1
fi
echo "world checks: the command line and Python agree"
