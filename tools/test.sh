#!/usr/bin/env bash
# Builds canopy with its tests and runs the whole suite through ctest (headless: the
# renderer uses OSMesa). Installs missing Debian packages first. Under CI (CI=true)
# compiler warnings are errors.
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
werror=OFF
[[ "${CI:-}" == "true" ]] && werror=ON
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCANOPY_BUILD_TESTS=ON \
  -DCANOPY_WARNINGS_AS_ERRORS="$werror" -DCANOPY_ONLY_MODULES= >/dev/null
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2 --timeout 900
