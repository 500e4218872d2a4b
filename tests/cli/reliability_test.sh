#!/usr/bin/env bash
# Reliability of the canopy CLI (issue 9): no shell strings from user input, worker count,
# --summarize-only and --resume, settings saved by world/render/map, a useful default render,
# and a video encoder that dies mid-run. Usage: reliability_test.sh path/to/canopy
set -u
canopy="$(realpath "$1")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# --- No shell strings: the very path of the issue, with the plots (python3) on. ------------
mkdir -p "$tmp/cwd"
weird="a'; touch X #"
log=$(cd "$tmp/cwd" && "$canopy" ablate --quick --views 2 --threads 8 --out "$weird" 2>&1); code=$?
[[ $code -eq 0 ]] || fail "ablate --out \"$weird\": exit $code: $log"
[[ ! -e "$tmp/cwd/X" ]] || fail "ablate --out \"$weird\" ran 'touch X'"
[[ -s "$tmp/cwd/$weird/summary.csv" && -f "$tmp/cwd/$weird/.canopy-output" ]] || fail "ablate did not write '$weird/summary.csv'"
[[ ! -e "$tmp/cwd/$weird.partial" ]] || fail "ablate left '$weird.partial'"
# 3 jobs (osamcep+rs with ours, osamcep with sparse): --threads 8 starts 3 workers.
[[ "$log" == *"= 3 jobs (0 reused), 2 views each, 3 workers"* ]] || fail "--threads 8 for 3 jobs: $(grep -o '[0-9]* workers' <<<"$log")"

# --- --resume and --summarize-only reuse the finished jobs. ---------------------------------
log=$(cd "$tmp/cwd" && "$canopy" ablate --quick --views 2 --resume --no-plots --out "$weird" 2>&1); code=$?
[[ $code -eq 0 && "$log" == *"(3 reused)"*"0 workers"* ]] || fail "--resume did not reuse the 3 jobs: $code: $log"
log=$(cd "$tmp/cwd" && "$canopy" ablate --quick --views 2 --summarize-only --no-plots --out "$weird" 2>&1); code=$?
[[ $code -eq 0 && "$log" == *"(3 reused)"* ]] || fail "--summarize-only on finished results: $code: $log"
# Other settings: nothing finished for them, so --summarize-only says so.
msg=$(cd "$tmp/cwd" && "$canopy" ablate --quick --views 3 --summarize-only --no-plots --out "$weird" 2>&1 >/dev/null); code=$?
[[ $code -eq 2 && "$msg" == *"run.yaml differs"* ]] || fail "--summarize-only with other settings: $code: $msg"
mkdir -p "$tmp/empty"
msg=$("$canopy" ablate --quick --summarize-only --out "$tmp/empty" 2>&1 >/dev/null); code=$?
[[ $code -eq 2 && "$msg" == *"--summarize-only: no finished jobs with these settings in '$tmp/empty'"* ]] \
  || fail "--summarize-only on an empty folder: $code: $msg"
[[ -z "$(ls -A "$tmp/empty" | grep -v '^.canopy-output$')" ]] || fail "--summarize-only wrote into an empty folder"

# --- world.json records the resolved parameters; they rebuild the same world. ---------------
"$canopy" world --out "$tmp/w1" >/dev/null 2>&1 || fail "canopy world"
python3 - "$tmp/w1/world.json" "$tmp/w1_spec.json" <<'PY' || fail "world.json lacks the resolved parameters"
import json, sys
w = json.load(open(sys.argv[1]))
s = w["spec"]
assert s["seed"] == w["seed"] == 1, s
assert s["rows"]["row_offset_m"] == 0.75 and s["plant"]["height_m"] == [1.0, 1.3], s
assert s["camera"]["fx_px"] == 381.36 and len(s["robot_start"]) == 3, s
json.dump(s, open(sys.argv[2], "w"))
PY
"$canopy" world --world "$tmp/w1_spec.json" --out "$tmp/w2" >/dev/null 2>&1 || fail "canopy world --world <saved spec>"
cmp -s "$tmp/w1/fruits.json" "$tmp/w2/fruits.json" && cmp -s "$tmp/w1/fruit_points.csv" "$tmp/w2/fruit_points.csv" \
  || fail "the saved world spec does not rebuild the same fruits"
diff <(grep -v '<!-- Generated' "$tmp/w1/scene.xml") <(grep -v '<!-- Generated' "$tmp/w2/scene.xml") >/dev/null \
  || fail "the saved world spec does not rebuild the same scene"

# --- render with no pose sees plants, and saves its settings. -------------------------------
log=$("$canopy" render --out "$tmp/r" 2>&1) || fail "canopy render: $log"
valid=$(grep -o '(\([0-9]*\) of 160000 depth pixels valid)' <<<"$log" | grep -o '^([0-9]*' | tr -d '(')
[[ -n "$valid" && "$valid" -gt 16000 ]] || fail "default render: ${valid:-?} of 160000 depth pixels valid (want > 10%)"
/usr/bin/python3 - "$tmp/r/run.yaml" <<'PY' || fail "render run.yaml"
import sys, yaml
s = yaml.safe_load(open(sys.argv[1]))
assert s["command"] == "render" and s["world"]["seed"] == 1 and len(s["joints"]) == 6 and len(s["base"]) == 3, s
PY

# --- map writes through DIR.partial and saves its settings. ---------------------------------
printf '0.0 0.3 0.7 0.5 -0.5 0.5 -0.5\n' > "$tmp/one_view.txt"
"$canopy" map --views "$tmp/one_view.txt" --out "$tmp/m" >/dev/null 2>&1 || fail "canopy map"
[[ -s "$tmp/m/metrics.json" && -s "$tmp/m/map.csm" && -f "$tmp/m/.canopy-output" && ! -e "$tmp/m.partial" ]] \
  || fail "canopy map did not write a complete folder"
/usr/bin/python3 - "$tmp/m/run.yaml" "$tmp/m/settings.yaml" <<'PY' || fail "map run.yaml and settings.yaml"
import sys, yaml
s = yaml.safe_load(open(sys.argv[1]))
assert s["command"] == "map" and s["world"]["seed"] == 1 and len(s["view_poses"]) == 1, s
b = yaml.safe_load(open(sys.argv[2]))
assert b["mapping"]["extractor"]["p_gt"] == 0.7 and b["method"]["name"] == "ours", b
PY
# A second map run replaces canopy's own folder.
"$canopy" map --views "$tmp/one_view.txt" --out "$tmp/m" >/dev/null 2>&1 || fail "canopy map over its own output"

# --- An encoder that dies mid-run: reported, the other results kept, no SIGPIPE (141). ------
mkdir -p "$tmp/bin"
printf '#!/bin/sh\nhead -c 100000 > /dev/null\nexit 1\n' > "$tmp/bin/ffmpeg"
chmod +x "$tmp/bin/ffmpeg"
msg=$(PATH="$tmp/bin:$PATH" "$canopy" run --world worlds/small.yaml --views-per-stop 1 --video "$tmp/run.mp4" --out "$tmp/run" 2>&1 >/dev/null); code=$?
[[ $code -eq 1 ]] || fail "run with a dying encoder: exit $code (want 1; 141 is death by SIGPIPE)"
[[ "$msg" == *"the video $tmp/run.mp4 is missing (ffmpeg stopped reading frames after"*"exited with code 1)"* ]] \
  || fail "run with a dying encoder does not say the video is missing: $(tail -2 <<<"$msg")"
[[ -s "$tmp/run/summary.json" && -s "$tmp/run/map.csm" ]] || fail "run with a dying encoder lost its results"
[[ ! -e "$tmp/run.mp4" && ! -e "$tmp/run.mp4.partial.mp4" && ! -e "$tmp/run.partial" ]] || fail "run left a video or partial files"

if [[ $failures -ne 0 ]]; then echo "$failures failure(s)"; exit 1; fi
echo "all reliability checks passed"
