#!/usr/bin/env bash
# canopy's main job: installs missing Debian packages, builds (Release, into build/) and runs
# `canopy run` on the default world, writing images and a summary to results/.
# Extra arguments go to `canopy run` (see ./build/canopy run --help).
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCANOPY_ONLY_MODULES= >/dev/null
cmake --build build -j2 --target canopy_cli
./build/canopy run --out results "$@"
