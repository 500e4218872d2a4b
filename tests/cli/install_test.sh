#!/usr/bin/env bash
# The installed package (issue 13): `cmake --install` into a temporary prefix; the installed
# CLI finds its data from outside any source tree and shows relative defaults; the example
# consumer (examples/plan_from_frames) configures with find_package(canopy COMPONENTS
# mapping nbv motion), builds without MuJoCo or OSMesa on its link line, and maps frames the
# installed CLI rendered. Issue 23: a consumer's own C++ planner (examples/own_planner, the
# mission component) runs the full mission; the installed Python module imports from the
# prefix's lib/python3/dist-packages and finds its data there.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR [PYTHON]   (PYTHON: "" when the module is not built)
set -u
build="$1"
src="$2"
python="${3:-}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

cmake --install "$build" --prefix "$prefix" >/dev/null || { echo "FAIL: cmake --install"; exit 1; }
for f in bin/canopy share/canopy/configs/canopy.yaml share/canopy/models/robot/robot.yaml share/canopy/worlds/small.yaml \
  lib/cmake/canopy/canopyConfig.cmake lib/cmake/canopy/canopyConfigVersion.cmake include/canopy/mapping/map_io.h; do
  [[ -e "$prefix/$f" ]] || fail "not installed: $f"
done

# The installed CLI, run from a folder without data: defaults relative, data found.
cd "$tmp"
help=$("$prefix/bin/canopy" map --help)
[[ "$help" == *"--world TEXT=worlds/default.yaml"* && "$help" == *"--config TEXT=configs/canopy.yaml"* ]] ||
  fail "canopy map --help does not show relative defaults: $help"
[[ "$help" != *"$src"* && "$help" != *"$build"* ]] || fail "canopy --help names the build machine's tree"
for i in 0 1 2; do
  "$prefix/bin/canopy" render --world worlds/small.yaml --joints -2.$((1 + 2 * i)),-0.6,2.3,1.3,-0.9,0.0 \
    --out "$tmp/frames/f$i" 2>/dev/null || fail "installed canopy render $i"
done
CANOPY_DATA_DIR="$tmp/nowhere" "$prefix/bin/canopy" world --out "$tmp/w" >/dev/null 2>&1 &&
  fail "CANOPY_DATA_DIR pointing at no data still found the data"
# The build tree's canopy, from outside the source tree: its relative pointer finds the data.
"$build/canopy" world --world worlds/small.yaml --out "$tmp/wb" >/dev/null 2>&1 || fail "build-tree canopy outside the tree"
grep -q "$src" "$build/canopy-data-dir" && fail "the build tree's pointer is absolute"

# The example, against the prefix only.
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src/examples/plan_from_frames" -B "$tmp/example" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" >"$tmp/configure.log" 2>&1 ||
  { cat "$tmp/configure.log"; echo "FAIL: configure the example"; exit 1; }
cmake --build "$tmp/example" -j2 >"$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; echo "FAIL: build the example"; exit 1; }
grep -qiE 'mujoco|osmesa' "$tmp/example/build.ninja" && fail "MuJoCo or OSMesa on the example's link line"
ldd "$tmp/example/plan_from_frames" | grep -qiE 'mujoco|osmesa' && fail "the example binary loads MuJoCo or OSMesa"
out=$(CANOPY_DATA_DIR="$prefix/share/canopy" "$tmp/example/plan_from_frames" "$tmp/frames" -0.3,0,0 2>&1) ||
  fail "the example failed: $out"
echo "$out"
[[ "$out" == *"mapped 3 frames (0 skipped)"* ]] || fail "the example did not map the 3 frames"
[[ "$out" =~ next\ views && "$out" == *"view 1: camera"* ]] || fail "the example printed no next view"

# The other components: sim resolves (MuJoCo found by the package), an unknown one fails.
mkdir -p "$tmp/sim_consumer"
cat >"$tmp/sim_consumer/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.22)
project(sim_consumer LANGUAGES C CXX)
find_package(canopy REQUIRED COMPONENTS sim)
if(NOT TARGET canopy::sim OR NOT TARGET canopy::motion)
  message(FATAL_ERROR "canopy::sim missing")
endif()
find_package(canopy QUIET COMPONENTS teleport)
if(canopy_FOUND)
  message(FATAL_ERROR "an unknown component was found")
endif()
CM
cmake -S "$tmp/sim_consumer" -B "$tmp/sim_consumer/build" -DCMAKE_PREFIX_PATH="$prefix" >"$tmp/sim.log" 2>&1 ||
  { cat "$tmp/sim.log"; fail "the sim component does not configure"; }

# A planner from outside the tree (issue 23): registered by the consumer, run in the full mission.
cmake -S "$src/examples/own_planner" -B "$tmp/own" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" >"$tmp/own_configure.log" 2>&1 ||
  { cat "$tmp/own_configure.log"; echo "FAIL: configure own_planner"; exit 1; }
cmake --build "$tmp/own" -j2 >"$tmp/own_build.log" 2>&1 || { cat "$tmp/own_build.log"; echo "FAIL: build own_planner"; exit 1; }
out=$(CANOPY_DATA_DIR="$prefix/share/canopy" "$tmp/own/own_planner" worlds/small.yaml "$tmp/own_run" 2>&1) ||
  fail "own_planner failed: $out"
echo "$out" | tail -2
[[ "$out" == *"planner 'nearest':"* ]] || fail "own_planner did not run its planner"
grep -q '"name": "nearest"' "$tmp/own_run/summary.json" || fail "the run folder does not name the planner 'nearest'"
nbv_ok=$(awk -F, 'NR > 1 && $3 == "nearest" && $4 == "nbv" && $6 == 1' "$tmp/own_run/views.csv" | wc -l)
((nbv_ok > 0)) || fail "no successful view of the planner 'nearest' in views.csv"

# The Python module, from the prefix, outside any source tree: data found beside it.
if [[ -n "$python" ]]; then
  ls "$prefix"/lib/python3/dist-packages/canopy/_canopy*.so >/dev/null 2>&1 || fail "not installed: the Python module"
  pyout=$(cd "$tmp" && env -u CANOPY_DATA_DIR PYTHONPATH="$prefix/lib/python3/dist-packages" PYTHONDONTWRITEBYTECODE=1 \
    "$python" -c '
import os, sys, canopy
assert os.path.samefile(canopy.data_dir(), sys.argv[1]), canopy.data_dir()
world = canopy.World("worlds/small.yaml")
assert "python" in canopy.planner_names()
print("python module:", len(world.plants), "plants from", canopy.data_dir())
' "$prefix/share/canopy" 2>&1) || fail "the installed Python module: $pyout"
  echo "$pyout"
fi

if ((failures)); then echo "$failures failure(s)"; exit 1; fi
echo "install: all checks passed"
