#!/usr/bin/env bash
# canopy map --frames and canopy nbv from the command line (its --set too): a rendered sequence maps and
# plans; bad input (missing folder, malformed TUM line, 8-bit or wrong-size depth, non-unit
# quaternion, unknown label colour, a map file of another version) gives one line naming
# the problem and exit code 2. Usage: frames_test.sh path/to/canopy
set -u
canopy="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

expect_error() {  # expect_error "<fragment of the message>" args...
  local fragment="$1"; shift
  local msg code
  msg=$("$canopy" "$@" 2>&1 >/dev/null)
  code=$?
  [[ $code -eq 2 ]] || fail "exit $code (want 2) for: $*"
  [[ "$msg" == *"$fragment"* ]] || fail "message '$msg' lacks '$fragment' for: $*"
  # Progress lines may come first; the error is one line, the last.
  [[ $(printf '%s\n' "$msg" | grep -c 'error') -eq 1 && $(printf '%s\n' "$msg" | tail -n 1) == "canopy: error: "* ]] ||
    fail "not one error line at the end: '$msg' for: $*"
}

# Two canopy frames of the small world, and the same as a TUM sequence (copied images; the
# depth is rescaled by the test's own writer below, so only the layout is exercised here).
"$canopy" render --world worlds/small.yaml --out "$tmp/seq/f0" 2>/dev/null || fail "render f0"
"$canopy" render --world worlds/small.yaml --joints -2.0,-0.6,2.3,1.3,-0.9,0.0 --out "$tmp/seq/f1" 2>/dev/null ||
  fail "render f1"
"$canopy" map --frames "$tmp/seq" --out "$tmp/map" >/dev/null 2>&1 || fail "map --frames"
python3 - "$tmp/map/frames.json" <<'PY' || fail "frames.json"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["frames_mapped"] == 2 and d["frames_skipped"] == 0, d
assert d["occupied_voxels"] > 100, d
PY
"$canopy" nbv --map "$tmp/map/map.csm" --base -0.3,0,0 --out "$tmp/views.json" >/dev/null 2>&1 || fail "nbv"
python3 - "$tmp/views.json" <<'PY' || fail "views.json"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["planner"] == "learned", d  # canopy nbv's default since issue 47's goal was met
for v in d["views"]:
    assert {"T_world_camera", "cluster", "gain", "joints", "tour_index"} <= set(v), v
PY

# Bad input.
expect_error "$tmp/nothing: no such folder" map --frames "$tmp/nothing" --out "$tmp/o"
mkdir -p "$tmp/tum/rgb" "$tmp/tum/depth"
cp "$tmp/seq/f0/rgb.png" "$tmp/tum/rgb/1.png"
cp "$tmp/seq/f0/depth.png" "$tmp/tum/depth/1.png"
printf 'width_px: 400\nheight_px: 400\nfx_px: 381.36\nfy_px: 381.36\ncx_px: 200\ncy_px: 200\ndepth_scale_per_m: 1000\n' \
  > "$tmp/tum/camera.yaml"
printf '# rgb\n1.0 rgb/1.png\n' > "$tmp/tum/rgb.txt"
printf '1.001 depth/1.png\n' > "$tmp/tum/depth.txt"
printf '# gt\n1.0 0 0 0.6 0 0 0 1\n1.0 0 0.6 0 0 0 1\n' > "$tmp/tum/groundtruth.txt"
expect_error "groundtruth.txt:3: expected 'timestamp tx ty tz qx qy qz qw', found 7 fields" \
  map --frames "$tmp/tum" --out "$tmp/o"
printf '# gt\n1.0 0 0 0.6 0.5 0.5 0 1\n' > "$tmp/tum/groundtruth.txt"
expect_error "groundtruth.txt:2: quaternion has norm" map --frames "$tmp/tum" --out "$tmp/o"
printf '1.0 0 0 0.6 0.5 0.5 0.5 0.5\n' > "$tmp/tum/groundtruth.txt"
"$canopy" map --frames "$tmp/tum" --out "$tmp/tum_map" >/dev/null 2>&1 || fail "a valid TUM folder does not map"
cp "$tmp/seq/f0/rgb.png" "$tmp/tum/depth/1.png"
expect_error "depth/1.png: expected a 16-bit grayscale PNG" map --frames "$tmp/tum" --out "$tmp/o"
cp "$tmp/seq/f0/depth.png" "$tmp/tum/depth/1.png"
sed -i 's/width_px: 400/width_px: 320/; s/cx_px: 200/cx_px: 160/' "$tmp/tum/camera.yaml"
expect_error "depth/1.png: image is 400x400 but the camera is 320x400" map --frames "$tmp/tum" --out "$tmp/o"
printf 'classes: [background, leaf, fruit]\ncolors: {background: [0, 0, 0], leaf: [0, 255, 0], fruit: [1, 2, 3]}\n' \
  > "$tmp/colors.yaml"
expect_error "labels.png: colour (" map --frames "$tmp/seq" --seg truth --label-colors "$tmp/colors.yaml" --out "$tmp/o"
[[ -e "$tmp/o" || -e "$tmp/o.partial" ]] && fail "output folder left behind"

# A map file of another format version.
python3 - "$tmp/map/map.csm" "$tmp/v2.csm" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
b[8:12] = struct.pack("<I", 99)
open(sys.argv[2], "wb").write(bytes(b))
PY
expect_error "v2.csm: semantic map format version 99 is not supported" nbv --map "$tmp/v2.csm" --base 0,0,0 --out "$tmp/v.json"
expect_error "cannot open" nbv --map "$tmp/none.csm" --base 0,0,0 --out "$tmp/v.json"
expect_error "--joints: value '9,9,9,9,9,9' is outside the joint limits" \
  nbv --map "$tmp/map/map.csm" --base 0,0,0 --joints 9,9,9,9,9,9 --out "$tmp/v.json"
expect_error "gain" nbv --map "$tmp/map/map.csm" --base 0,0,0 --gain nonsense --out "$tmp/v.json"
# --set: any setting of the bundle (a lab's own view ranker model, a planner's parameter).
"$canopy" nbv --map "$tmp/map/map.csm" --base -0.3,0,0 --method ours --set nbv.ours.top_k=1 --out "$tmp/views_k1.json" >/dev/null 2>&1 ||
  fail "nbv --set"
python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); assert d["k"] == 1, d["k"]' "$tmp/views_k1.json" ||
  fail "nbv --set nbv.ours.top_k=1: k 1 in views.json"
expect_error "view ranker model '$tmp/no_model.json': no such file" \
  nbv --map "$tmp/map/map.csm" --base 0,0,0 --method learned --set "nbv.learned.model=$tmp/no_model.json" --out "$tmp/v.json"
expect_error "nbv.no_such_key" nbv --map "$tmp/map/map.csm" --base 0,0,0 --set nbv.no_such_key=1 --out "$tmp/v.json"
expect_error "--out: folder '$tmp/nodir' does not exist" nbv --map "$tmp/map/map.csm" --base 0,0,0 --out "$tmp/nodir/v.json"
[[ -e "$tmp/v.json" ]] && fail "views file written on bad input"

if ((failures)); then echo "$failures failure(s)"; exit 1; fi
echo "frames and nbv CLI: all checks passed"
