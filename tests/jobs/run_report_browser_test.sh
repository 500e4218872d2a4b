#!/usr/bin/env bash
# report.html in a real browser (Debian's headless chromium, tests/jobs/report_browser.py):
# a small mission's report opens from file:// without a console error, its 3D view is not
# blank (leaf and fruit colours in a screenshot of the canvas), the slider changes the cameras
# drawn, the map and the curve cursor; what RViz users look for (axes, scale, robot, orbit hint
# and reset, ticks, a fruit table, labelled metrics, 1-based stops, the labels mapped beside the
# truth, entropy colours apart from the fruits', the views that saw each fruit as counted from the
# mission's exported frames); an interrupted mission's report says it is incomplete;
# equal seeds give the same report bytes (but for the wall-time line) and thumbnails; an
# experiment report's links to its trials' reports resolve, and it goes without three.js with
# its means over the trials' lines and ticks on both axes; canopy map's report opens too, with
# its labels mapped;
# --no-report writes none; both pages open with "<!--<script>" in every user string of their
# data. One browser opens every page.
set -euo pipefail
canopy=$1
jobs_tests=$2
src=$(pwd)
if [[ -n "${TEST_TMPDIR:-}" ]]; then
  dir="$TEST_TMPDIR/report_browser"
else
  dir=$(mktemp -d)
  trap 'rm -rf "$dir"' EXIT
fi
rm -rf "$dir" && mkdir -p "$dir"
browser="python3 $src/tests/jobs/report_browser.py"

run() { "$canopy" mission --world worlds/small.yaml --views-per-stop 3 --no-plots "$@" 2>> "$dir/log.txt"; }
run --seed 1 --out "$dir/a" --export "$dir/a_frames"  # its frames: the views that saw each fruit, counted apart
run --seed 1 --out "$dir/b"
for f in "$dir"/a/report*; do
  name=$(basename "$f")
  if [[ $name == report.html ]]; then
    cmp <(grep -v '^<script id="canopy-wall"' "$f") <(grep -v '^<script id="canopy-wall"' "$dir/b/$name") ||
      { echo "report.html differs between equal seeds"; exit 1; }
  else
    cmp "$f" "$dir/b/$name" || { echo "$name differs between equal seeds"; exit 1; }
  fi
done
[[ $(grep -c '^<script id="canopy-wall"' "$dir/a/report.html") -eq 1 ]] || { echo "no wall-time line"; exit 1; }
# The labels mapped (colour segmentation, P_gt 0.7) are thumbnailed beside the true ones, and differ.
[[ -s "$dir/a/report_mapped_0.png" ]] || { echo "no thumbnails of the labels mapped"; exit 1; }
! cmp -s "$dir/a/report_mapped_0.png" "$dir/a/report_labels_0.png" ||
  { echo "the labels mapped are the true labels at P_gt 0.7"; exit 1; }

# The views that saw each fruit, from the exported frames (Debian's python3: numpy, PIL).
/usr/bin/python3 "$src/tests/jobs/fruit_views.py" "$dir/a_frames" > "$dir/fruit_views.json"

# Ctrl-C after the first views: the report says the run is incomplete.
"$canopy" mission --world worlds/small.yaml --views-per-stop 12 --no-plots --out "$dir/int" 2> "$dir/int.log" &
pid=$!
for _ in $(seq 1 600); do
  grep -q "initial view 2 " "$dir/int.log" && break
  sleep 0.1
done
kill -INT "$pid"
set +e
wait "$pid"
code=$?
set -e
[[ $code -eq 130 ]] || { echo "interrupted mission: exit $code, expected 130"; cat "$dir/int.log"; exit 1; }

# --no-report: no report.
run --seed 2 --out "$dir/none" --no-report
[[ ! -e "$dir/none/report.html" ]] || { echo "--no-report wrote report.html"; exit 1; }

# An experiment of two trials and its report; every trial linked to its own report.
cat > "$dir/exp.yaml" <<YAML
name: report_browser
world: $src/worlds/small.yaml
overrides:
  mission: {loop: {views_per_stop: 1}}
methods:
  - {label: ours, method: ours}
p_gt: [1.0]
seeds: [1, 2]
trial_timeout_s: 120
YAML
"$canopy" experiment --config "$dir/exp.yaml" --out "$dir/exp" --jobs 2 2>> "$dir/log.txt"
mkdir "$dir/exp/trials/x<!--<script>.partial"  # listed by the report: its name reaches the page's data
"$canopy" report "$dir/exp" --no-plots 2>> "$dir/log.txt"
grep -q 'x\\u003c!--\\u003cscript>.partial' "$dir/exp/report/report.html" ||
  { echo "the experiment page does not list the folder trials/x<!--<script>.partial"; exit 1; }

# Both pages written again with every user string of their data holding "<!--<script>" (which
# once blanked them), by the page writer with the real scripts (tests/jobs/run_report_test.cpp).
poison() { CANOPY_POISONED_REPORT="$1:$2:$3" "$jobs_tests" --gtest_filter=RunReport.NoLessThanSignReachesThePageFromItsData > /dev/null; }
poison "$dir/a/report.html" "$dir/a/poisoned.html" report.js
poison "$dir/exp/report/report.html" "$dir/exp/report/poisoned.html" experiment_report.js

# canopy map's report, of three views, with the labels it mapped beside the truth (P_gt 0.3: at
# 0.7 none of the three views' masks is flipped).
"$canopy" map --world worlds/small.yaml --views tests/jobs/report_map_views.txt --pgt 0.3 --out "$dir/map" > /dev/null 2>> "$dir/log.txt"
[[ -s "$dir/map/report_mapped_0.png" ]] || { echo "canopy map's report has no thumbnails of the labels mapped"; exit 1; }
! cmp -s "$dir/map/report_mapped_0.png" "$dir/map/report_labels_0.png" ||
  { echo "canopy map's labels mapped (P_gt 0.3) are the true labels"; exit 1; }

$browser ${REPORT_SHOTS:+--shots "$REPORT_SHOTS"} --fruit-views "$dir/fruit_views.json" mission "$dir/a/report.html" incomplete "$dir/int/report.html" run "$dir/map/report.html" \
  experiment "$dir/exp/report/report.html" poisoned "$dir/a/poisoned.html" poisoned "$dir/exp/report/poisoned.html"
echo "report browser test: ok"
