#!/usr/bin/env bash
# canopy's main job: installs missing Debian packages, builds (Release, into build/) and runs
# `canopy run`, the default closed-loop mission (method ours) on the default world, writing
# views.csv, summary.json, the map and the plots to results/. Extra arguments go to
# `canopy run` (see ./build/canopy run --help), e.g. `./tools/run.sh --video results/run.mp4`.
# It also builds the Python module (PYTHONPATH=build/python python3 -c 'import canopy').
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCANOPY_UNITY_BUILD=ON -DCANOPY_ONLY_MODULES= >/dev/null
cmake --build build -j2 --target canopy_cli canopy_python
./build/canopy run --out results "$@"
