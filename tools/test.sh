#!/usr/bin/env bash
# Builds canopy with its tests and runs the whole suite through ctest (headless: the
# renderer uses OSMesa). Installs missing Debian packages first. Under CI (CI=true)
# compiler warnings are errors.
#   ./tools/test.sh              Release build in build/
#   ./tools/test.sh --sanitize   AddressSanitizer + UndefinedBehaviorSanitizer build
#                                (-O1 with line tables) in build-asan/; any finding fails its test
# Both are unity builds (CANOPY_UNITY_BUILD): from scratch on 2 cores that halves the build.
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize=false
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=true ;;
    *) echo "usage: $0 [--sanitize]" >&2; exit 2 ;;
  esac
done
./tools/deps.sh
werror=OFF
[[ "${CI:-}" == "true" ]] && werror=ON
# ccache hits across checkouts in other folders (CI clones): paths relative to the tree,
# and debug builds do not hash the build folder.
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
build=build
flags=(-DCMAKE_BUILD_TYPE=Release -DCANOPY_SANITIZE=OFF)
if $sanitize; then
  build=build-asan
  # -O1 -g1: ASan's recommended optimisation and file:line in reports, at under half the
  # compile time of -O2 -g.
  flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DCANOPY_SANITIZE=ON
         "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG")
  # Leaks: only the known ones inside libOSMesa's context creation are suppressed.
  export ASAN_OPTIONS="detect_leaks=1"
  export LSAN_OPTIONS="suppressions=$PWD/tools/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
fi
cmake -S . -B "$build" -G Ninja "${flags[@]}" -DCANOPY_BUILD_TESTS=ON -DCANOPY_UNITY_BUILD=ON \
  -DCANOPY_WARNINGS_AS_ERRORS="$werror" -DCANOPY_ONLY_MODULES= >/dev/null
cmake --build "$build" -j2
ctest --test-dir "$build" --output-on-failure -j2 --timeout 900
