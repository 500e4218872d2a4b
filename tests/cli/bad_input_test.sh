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

# Configs cannot be silently wrong.
printf 'seed: 1\nname: twice\nseed: 2\n' > "$tmp/duplicate.yaml"
printf 'rows: {row_offset_m: 0.3}\n' > "$tmp/narrow.yaml"
printf 'plant: {height_m: [1.0e30, 1.0e30]}\n' > "$tmp/huge.yaml"
mkdir -p "$tmp/a_folder"
expect_error "$tmp/a_folder: is a folder" world --world "$tmp/a_folder"
expect_error "$tmp/a_folder: is a folder" map --config "$tmp/a_folder"
expect_error "$tmp/a_folder: is a folder" ablate --quick --config "$tmp/a_folder"
expect_error "duplicate key 'seed' at lines 1 and 3" world --world "$tmp/duplicate.yaml"
expect_error "key 'rows.row_offset_m': value '0.3' leaves an aisle" world --world "$tmp/narrow.yaml"
expect_error "key 'plant.height_m'" world --world "$tmp/huge.yaml"
expect_error "--pgt: value 'nan' is not a finite number" map --pgt nan
expect_error "--pgt" map --pgt inf
expect_error "--distance: value 'nan' is not a finite number" visibility --distance nan
expect_error "--distance must be > 0" visibility --distance 0
expect_error "--max-occlusion must be in [0, 1]" visibility --max-occlusion 2
expect_error "--video-fps: value 'nan' is not a finite number" run --video-fps nan
expect_error "--coverage-target: value 'nan' is not a finite number" ablate --coverage-target nan
expect_error "excludes" render --base 0,0,0 --camera-pose 0,0,1,1,0,0,0
expect_error "--joints: value '7,0,0,0,0,0' is outside the joint limits" render --joints 7,0,0,0,0,0

# Messages tell the truth.
expect_error "unknown command 'frobnicate' for 'canopy'; the commands are: world, render, import-plant, run, mission, map, export-mcap, ablate, experiment, report, reach, visibility, nbv, settings, bench" frobnicate
expect_error "unknown command 'frobnicate' for 'canopy bench'; the commands are: render, map, gain, motion" bench frobnicate
expect_error "--summarize-only: no finished jobs" ablate --quick --summarize-only

# Video paths are checked before the run starts.
expect_error "--video: cannot write '$tmp/no_such_folder/v.mp4': folder '$tmp/no_such_folder' does not exist" \
  run --video "$tmp/no_such_folder/v.mp4"
expect_error "--video: '$tmp/a_folder' is a folder" run --video "$tmp/a_folder"
expect_error "--video: cannot write '/proc/canopy.mp4'" run --video /proc/canopy.mp4
# A key given twice, a seed given twice, lists beyond their limits (issue 45, point 10).
expect_error "--set: key 'mission.loop.views_per_stop' is given twice ('mission.loop.views_per_stop=2' and 'mission.loop.views_per_stop=3'); give it once" \
  mission --world worlds/small.yaml --set mission.loop.views_per_stop=2 --set mission.loop.views_per_stop=3
expect_error "--seed: seed 1 is given twice" visibility --seed 1,1
expect_error "holds more than 16 radii" mission --world worlds/small.yaml --method shape \
  --set "nbv.shape.radii_m=[$(seq -s, 0.3 0.01 0.5)]"
expect_error "holds 1001 numbers, at most 1000" mission --world worlds/small.yaml \
  --set "mission.record.time_budgets_s=[$(seq -s, 1 1001)]"

# The learned planner's model (docs/learned.md): missing, corrupt, trained on other features or
# without its fruit-value model is one line naming the file, exit 2, never a silent fallback to
# another scorer.
printf '{"learner": [1, 2' > "$tmp/corrupt_model.json"
sed 's/"shape_seen"/"shape_sen"/' models/nbv/view_ranker.json > "$tmp/renamed_model.json"
# A model reading fruit_value (--fruit-value) without the fruit-value model it needs beside it.
sed 's/"shape_seen"/"fruit_value"/' models/nbv/view_ranker.json > "$tmp/no_fruit_model.json"
for model in "$tmp/missing_model.json:no such file" "$tmp/corrupt_model.json:not an XGBoost model" \
  "$tmp/renamed_model.json:feature 17 is 'shape_sen', which this canopy does not compute" \
  "$tmp/no_fruit_model.json:it reads fruit_value but names no fruit-value model file beside it"; do
  file="${model%%:*}"
  expect_error "view ranker model '$file': ${model#*:}" mission --world worlds/small.yaml --method learned \
    --set "nbv.learned.model=$file"
  # One line: the error, after the log's info lines, and nothing after it.
  msg=$("$canopy" mission --world worlds/small.yaml --method learned --set "nbv.learned.model=$file" \
    --out "$tmp/learned_out" 2>&1 >/dev/null | sed -n '/error/,$p')
  if [[ $(printf '%s\n' "$msg" | wc -l) -ne 1 || "$msg" != "canopy: error: view ranker model '$file': "* ]]; then
    echo "FAIL: the refusal of $file is not one line: $msg"; failures=$((failures + 1))
  fi
done

# Every command protects a folder it did not write: map and ablate (with or without
# --resume) refuse it and leave the user's files as they were.
for cmd in "map --views $tmp/one_view.txt" "ablate --quick --views 2 --no-plots" "ablate --quick --views 2 --no-plots --resume" \
  "ablate --quick --summarize-only" "world" "render"; do
  rm -rf "$tmp/user" && mkdir -p "$tmp/user" && echo mine > "$tmp/user/metrics.json" && echo mine > "$tmp/user/settings.json"
  printf '0.0 0.3 0.7 0.5 -0.5 0.5 -0.5\n' > "$tmp/one_view.txt"
  msg=$("$canopy" $cmd --out "$tmp/user" 2>&1 >/dev/null); code=$?
  if [[ $code -ne 2 || "$msg" != *"'$tmp/user' is not empty and was not written by canopy"* ]]; then
    echo "FAIL: $cmd --out <user folder>: exit $code: $msg"; failures=$((failures + 1))
  fi
  if [[ "$(cat "$tmp/user/metrics.json" "$tmp/user/settings.json")" != $'mine\nmine' || $(ls -A "$tmp/user" | wc -l) -ne 2 \
        || -e "$tmp/user.partial" ]]; then
    echo "FAIL: $cmd changed the user's folder"; failures=$((failures + 1))
  fi
done

# ROS 2 recordings (docs/ros2.md): one line naming the file, exit 2, nothing written.
printf 'not an mcap' > "$tmp/text.mcap"
printf '\x89MCAP0\r\n\x01\x00\x00' > "$tmp/cut.mcap"
expect_error "$tmp/text.mcap: not an MCAP file" map --mcap "$tmp/text.mcap"
expect_error "$tmp/cut.mcap: truncated MCAP file" map --mcap "$tmp/cut.mcap"
expect_error "$tmp/missing.mcap" map --mcap "$tmp/missing.mcap"
expect_error "--rgb requires --mcap" map --rgb /camera/color/image_raw
expect_error "--mcap-compression: 'bz2' is not none, lz4 or zstd" mission --mcap "$tmp/run.mcap" --mcap-compression bz2
expect_error "an MCAP file's name ends in .mcap" mission --mcap "$tmp/run.bag"
expect_error "--mcap-epoch: 'soon' is not 'run'" mission --mcap "$tmp/run.mcap" --mcap-epoch soon
msg=$("$canopy" export-mcap "$tmp" "$tmp/x.mcap" 2>&1 >/dev/null); code=$?
if [[ $code -ne 2 || "$msg" != *"not a canopy mission run folder (no summary.json)"* || -e "$tmp/x.mcap" ]]; then
  echo "FAIL: export-mcap of a folder that is no run ($code: $msg)"; failures=$((failures + 1))
fi

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
