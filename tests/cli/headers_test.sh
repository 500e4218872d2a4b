#!/usr/bin/env bash
# The installed package's interface: `cmake --install` into a temporary prefix, then every
# installed header compiled on its own (its own translation unit, -fsyntax-only, against the
# package's targets only: a header that leans on what another header included fails), and
# find_package(canopy 0.2) finds it while find_package(canopy 0.1) does not (a minor version
# of 0.x may break the interface; CHANGELOG.md lists what did).
# Usage: headers_test.sh BUILD_DIR
# The check works in BUILD_DIR/header_check, not in a fresh temporary folder: its paths are then
# the same in every checkout below CCACHE_BASEDIR (tools/test.sh sets it to the tree), so ccache
# answers for every header whose text and includes did not change (-fsyntax-only is cached).
set -u
build=$(cd "$1" && pwd)
tmp="$build/header_check"
rm -rf "$tmp"
mkdir -p "$tmp"
trap 'rm -rf "$tmp"' EXIT
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$tmp}" CCACHE_NOHASHDIR=true
prefix="$tmp/prefix"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cmake --install "$build" --prefix "$prefix" >/dev/null || { echo "FAIL: cmake --install"; exit 1; }
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
mkdir -p "$tmp/sim_consumer"
cat >"$tmp/sim_consumer/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.22)
project(sim_consumer LANGUAGES C CXX)
find_package(canopy REQUIRED COMPONENTS sim)
CM

mkdir -p "$tmp/headers"
{
  echo 'cmake_minimum_required(VERSION 3.22)'
  echo 'project(headers LANGUAGES C CXX)'
  echo 'find_package(canopy 0.2 REQUIRED COMPONENTS sim)'
  echo 'if(NOT canopy_VERSION VERSION_EQUAL 0.2.0)'
  echo '  message(FATAL_ERROR "canopy ${canopy_VERSION}, not 0.2.0")'
  echo 'endif()'
  echo 'add_library(headers OBJECT'
  (cd "$prefix/include" && find canopy -name '*.h' | sort) | while read -r h; do
    tu="$tmp/headers/$(tr '/.' '__' <<<"$h").cpp"
    printf '#include <%s>\n' "$h" > "$tu"
    echo "  $tu"
  done
  echo ')'
  echo 'target_link_libraries(headers PRIVATE canopy::jobs)'
  echo 'target_compile_options(headers PRIVATE -fsyntax-only)  # parsed and checked, no code generated'
  echo 'set_target_properties(headers PROPERTIES CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON)'
} > "$tmp/headers/CMakeLists.txt"
headers=$(ls "$tmp"/headers/*.cpp | wc -l)
((headers > 100)) || fail "only $headers installed headers found"
cmake -S "$tmp/headers" -B "$tmp/headers/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" \
  >"$tmp/headers.log" 2>&1 || { cat "$tmp/headers.log"; fail "configure the header check"; }
if cmake --build "$tmp/headers/build" -j2 -- -k 0 >"$tmp/headers_build.log" 2>&1; then
  echo "installed headers: $headers compile on their own"
else
  grep -E "FAILED|error" "$tmp/headers_build.log" | head -20
  fail "an installed header does not compile on its own"
fi
sed -i 's/find_package(canopy REQUIRED COMPONENTS sim)/find_package(canopy 0.1 REQUIRED COMPONENTS sim)/' \
  "$tmp/sim_consumer/CMakeLists.txt"
cmake -S "$tmp/sim_consumer" -B "$tmp/old_version" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null 2>&1 &&
  fail "find_package(canopy 0.1) accepted 0.2 (a minor version of 0.x may break the interface)"


if ((failures)); then echo "$failures failure(s)"; exit 1; fi
echo "headers: all checks passed"
