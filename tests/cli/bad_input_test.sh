#!/usr/bin/env bash
# Bad input to the canopy CLI: one-line error naming the problem, exit code 2, and no
# output folder left behind. Usage: bad_input_test.sh path/to/canopy
set -u
canopy="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0

expect_error() {  # expect_error "<fragment of the message>" args...
  local fragment="$1"; shift
  local out="$tmp/out"
  rm -rf "$out" "$out.partial"
  local msg
  msg=$("$canopy" "$@" --out "$out" 2>&1 >/dev/null)
  local code=$?
  if [[ $code -ne 2 ]]; then echo "FAIL: exit $code (want 2) for: $*"; failures=$((failures + 1)); fi
  if [[ "$msg" != *"$fragment"* ]]; then echo "FAIL: message '$msg' lacks '$fragment' for: $*"; failures=$((failures + 1)); fi
  if [[ -e "$out" || -e "$out.partial" ]]; then echo "FAIL: output folder left behind for: $*"; failures=$((failures + 1)); fi
}

printf 'seed: 1\nrows: {plants_per_row: 2, spacing: 3}\n' > "$tmp/unknown_key.yaml"
printf 'plant: {leaf_length_m: [-0.1, 0.1]}\n' > "$tmp/negative.yaml"
printf 'camera: {fx_px: 0}\n' > "$tmp/fx.yaml"
printf 'rows: [1, 2\n' > "$tmp/malformed.yaml"

expect_error "$tmp/missing.yaml: cannot open file" world --world "$tmp/missing.yaml"
expect_error "unknown key 'rows.spacing'" world --world "$tmp/unknown_key.yaml"
expect_error "key 'plant.leaf_length_m': value '[-0.1, 0.1]'" world --world "$tmp/negative.yaml"
expect_error "key 'camera.fx_px': value '0'" render --world "$tmp/fx.yaml"
expect_error "malformed YAML" render --world "$tmp/malformed.yaml"
expect_error "--camera-pose: value '1,2,3,1,1,0,0': quaternion" render --camera-pose 1,2,3,1,1,0,0
expect_error "--base: value '1,x,0'" render --base 1,x,0
expect_error "--joints" render --joints 1,2,3
expect_error "excludes" render --joints 0,0,0,0,0,0 --camera-pose 0,0,1,1,0,0,0

# An existing folder that canopy did not write is never replaced.
mkdir -p "$tmp/foreign" && echo keep > "$tmp/foreign/precious.txt"
msg=$("$canopy" world --out "$tmp/foreign" 2>&1 >/dev/null); code=$?
if [[ $code -ne 2 || "$msg" != *"not written by canopy"* || ! -f "$tmp/foreign/precious.txt" ]]; then
  echo "FAIL: a foreign --out folder was not protected ($code: $msg)"; failures=$((failures + 1))
fi

# A good call leaves a complete folder and no staging folder.
if ! "$canopy" world --out "$tmp/good" >/dev/null 2>&1 || [[ ! -f "$tmp/good/scene.xml" || -e "$tmp/good.partial" ]]; then
  echo "FAIL: canopy world did not write a complete folder"; failures=$((failures + 1))
fi
if [[ $failures -ne 0 ]]; then echo "$failures failure(s)"; exit 1; fi
echo "all bad-input checks passed"
