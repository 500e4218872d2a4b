#!/usr/bin/env bash
# canopy mission --video on the small world (real ffmpeg): the MP4 has the asked frame size
# and one frame per 1/fps of simulated time, and its map inset (bottom left) is empty before
# the first view and shows class-coloured voxels at the end.
set -euo pipefail
canopy="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
command -v ffmpeg > /dev/null || { echo "ffmpeg not installed"; exit 1; }

"$canopy" mission --world worlds/small.yaml --views-per-stop 2 --no-plots --out "$dir/run" \
  --video "$dir/run.mp4" --video-size 320x240 --video-fps 10 2>/dev/null
ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,width,height,nb_frames -of csv=p=0 \
  "$dir/run.mp4" > "$dir/stream.csv"
ffmpeg -loglevel error -i "$dir/run.mp4" -f rawvideo -pix_fmt rgb24 "$dir/frames.rgb"
python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
codec, w, h, frames = open(f"{d}/stream.csv").read().strip().split(",")
assert (codec, w, h) == ("h264", "320", "240"), (codec, w, h)
s = json.load(open(f"{d}/run/summary.json"))
expected = s["simulated_time_s"] * 10
assert abs(int(frames) - expected) <= 2, f"{frames} frames for {s['simulated_time_s']} s simulated at 10 fps"
assert s["video"]["frames"] == int(frames), (s["video"], frames)

# The map inset: 80 x 60 pixels at (8, 240 - 60 - 8), as MissionVideo::map_inset_rect places it.
W, H, iw, ih = 320, 240, 80, 60
x0, y0 = 8, H - ih - 8
leaf, fruit = (40, 170, 40), (220, 30, 30)  # SemanticClasses::color of leaf and fruit
raw = open(f"{d}/frames.rgb", "rb").read()
assert len(raw) == int(frames) * W * H * 3, (len(raw), frames)
def coloured(i):
    px = raw[i * W * H * 3:(i + 1) * W * H * 3]
    n = {"leaf": 0, "fruit": 0}
    for y in range(y0 + 2, y0 + ih - 2):  # inside the border (H.264 blurs it into its neighbours)
        for x in range(x0 + 2, x0 + iw - 2):
            p = px[3 * (y * W + x): 3 * (y * W + x) + 3]
            for name, c in (("leaf", leaf), ("fruit", fruit)):
                if sum(abs(a - b) for a, b in zip(p, c)) < 90:
                    n[name] += 1
    return n
first, last = coloured(0), coloured(int(frames) - 1)
assert first["leaf"] + first["fruit"] < 5, f"map inset not empty before the first view: {first}"
assert last["leaf"] > 20 and last["fruit"] > 3, f"map inset without class-coloured voxels at the end: {last}"
print(f"mission video: ok ({frames} frames for {s['simulated_time_s']:.1f} s simulated; map inset at the end: {last})")
PY
