#!/usr/bin/env bash
# canopy bench mission --against / --save (tools/cmd_bench_mission.cpp, jobs/bench_compare.h):
# bad input is one line and exit code 2; two builds (here the same binary twice, and a saved
# measurement) run the same mission on the small world and their views.csv and map.csm are
# reported identical. Timings are printed, never checked. Usage: bench_mission_test.sh canopy
set -u
canopy="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export TMPDIR="$tmp"
fail=0
small=(--world worlds/small.yaml --set mission.loop.views_per_stop=2 --repeats 1)

expect_error() {  # expect_error "<fragment of the message>" args...
  local fragment="$1"; shift
  local msg
  msg=$("$canopy" bench mission "$@" 2>&1 >/dev/null)
  local code=$?
  if [[ $code -ne 2 ]]; then echo "FAIL: exit $code (want 2) for: $*"; fail=1; fi
  if [[ "$msg" != *"$fragment"* ]]; then echo "FAIL: message '$msg' lacks '$fragment' for: $*"; fail=1; fi
  if [[ $(printf '%s\n' "$msg" | grep -c .) -ne 1 ]]; then echo "FAIL: not one line: '$msg'"; fail=1; fi
}
printf '{"wall_s": [1.0]}\n' > "$tmp/partial.json"
printf 'not json\n' > "$tmp/garbage.json"
expect_error "--against: '$tmp/missing' is not an executable canopy" --against "$tmp/missing" "${small[@]}"
expect_error "not a measurement saved by canopy bench mission --save" --against "$tmp/partial.json" "${small[@]}"
expect_error "is not JSON" --against "$tmp/garbage.json" "${small[@]}"
expect_error "--repeats" --against "$canopy" --repeats 0

# The same build on both sides: the same views and map.
out=$("$canopy" bench mission --against "$canopy" "${small[@]}" --save "$tmp/m.json" 2>/dev/null) || { echo "FAIL: --against itself"; fail=1; }
echo "$out"
for want in "ratio new/old:" "views.csv identical, map.csm identical" "saved: $tmp/m.json"; do
  [[ "$out" == *"$want"* ]] || { echo "FAIL: output lacks '$want'"; fail=1; }
done
# A saved measurement as the old side.
out=$("$canopy" bench mission --against "$tmp/m.json" "${small[@]}" 2>/dev/null) || { echo "FAIL: --against saved"; fail=1; }
echo "$out"
for want in "saved" "not interleaved" "views.csv identical, map.csm identical"; do
  [[ "$out" == *"$want"* ]] || { echo "FAIL: output lacks '$want'"; fail=1; }
done
# No run folder is left in the temporary folder.
left=$(find "$tmp" -maxdepth 1 -name 'canopy-bench-*' | wc -l)
[[ "$left" -eq 0 ]] || { echo "FAIL: $left temporary folder(s) left"; fail=1; }
exit $fail
