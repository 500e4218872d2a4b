#!/usr/bin/env bash
# canopy mission from the command line, on the small world: bad options are clean errors; the
# video is a real H.264 MP4 and does not change the results; a saved settings.yaml repeats
# the run; Ctrl-C leaves a valid partial result marked incomplete.
set -euo pipefail
canopy="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
small=(--world worlds/small.yaml --views-per-stop 2 --no-plots)

for bad in "--method greedy" "--gain entropy" "--rays all" "--pgt 1.5" "--pgt nan" "--stops 0.1,abc" \
           "--video-size 1x1 --video $dir/v.mp4" "--video-fps 0 --video $dir/v.mp4" "--config /tmp"; do
  set +e
  msg=$("$canopy" mission "${small[@]}" $bad --out "$dir/bad" 2>&1 >/dev/null)
  code=$?
  set -e
  [[ $code -eq 2 ]] || { echo "mission $bad: exit $code, expected 2 ($msg)"; exit 1; }
  first=${bad%% *}
  [[ "$msg" == *"$first"* ]] || { echo "mission $bad: message does not name $first: $msg"; exit 1; }
  [[ $(echo "$msg" | grep -c "error") -eq 1 ]] || { echo "mission $bad: not one error line: $msg"; exit 1; }
  [[ ! -e "$dir/bad" ]] || { echo "mission $bad: left an output folder"; exit 1; }
done

"$canopy" mission "${small[@]}" --out "$dir/plain" 2>/dev/null
"$canopy" mission "${small[@]}" --out "$dir/video" --video "$dir/run.mp4" --video-size 320x240 --video-fps 8 2>/dev/null
for f in views.csv timing.csv summary.json settings.yaml map.csm map.ply map.bt; do
  [[ -s "$dir/plain/$f" ]] || { echo "missing $f"; exit 1; }
done
cmp "$dir/plain/views.csv" "$dir/video/views.csv" || { echo "the video changed views.csv"; exit 1; }
codec=$(ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,width,height,nb_frames -of csv=p=0 "$dir/run.mp4")
[[ "$codec" == h264,320,240,* ]] || { echo "video stream: $codec"; exit 1; }
frames=${codec##*,}
(( frames > 20 )) || { echo "video has only $frames frames"; exit 1; }

# The saved bundle repeats the run.
"$canopy" mission "${small[@]}" --config "$dir/plain/settings.yaml" --out "$dir/again" 2>/dev/null
cmp "$dir/plain/views.csv" "$dir/again/views.csv" || { echo "settings.yaml did not repeat the run"; exit 1; }

# Ctrl-C after the first views: exit 130, a valid partial result marked incomplete.
"$canopy" mission --world worlds/small.yaml --views-per-stop 12 --no-plots --out "$dir/int" \
  --video "$dir/int.mp4" --video-size 320x240 --video-fps 25 2> "$dir/int.log" &
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
python3 - "$dir/int" <<'PY'
import csv, json, sys
run = sys.argv[1]
s = json.load(open(f"{run}/summary.json"))
assert s["complete"] is False and s["end_reason"] == "interrupted", s["end_reason"]
rows = list(csv.DictReader(open(f"{run}/views.csv")))
assert 2 <= len(rows) < 24, len(rows)
assert s["views_attempted"] == len(rows)
print("mission cli: ok (bad options, video, settings round trip, interrupt after", len(rows), "views)")
PY
