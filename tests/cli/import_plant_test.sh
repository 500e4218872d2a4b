#!/usr/bin/env bash
# canopy import-plant end to end: the test writes its own COLLADA plant (Z-up, 0.0254 scale
# in the node, stem + leaf, two ripe fruits, one unripe), imports it, places it in a world
# next to a procedural plant, and runs canopy world and canopy map on that world. Then bad
# input: exit code 2, a one-line error, no plant folder left. Usage: import_plant_test.sh canopy
set -u
canopy="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

python3 - "$tmp" <<'PY'
import sys
tmp = sys.argv[1]
inch = 0.0254
def box(lo, hi):
    v = lambda i: ((hi if i & 1 else lo)[0], (hi if i & 2 else lo)[1], (hi if i & 4 else lo)[2])
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    out = []
    for a, b, c, d in quads:
        out += [(v(a), v(b), v(c)), (v(a), v(c), v(d))]
    return out
def cube(c, s):
    return box([x - s / 2 for x in c], [x + s / 2 for x in c])
m = lambda t: [tuple(tuple(x / inch for x in p) for p in tri) for tri in t]  # metres -> inches
groups = [("Pepper_brn", (0.35, 0.5, 0.2), m(box((-0.01, -0.01, 0), (0.01, 0.01, 1.0)))),
          ("Pepper_lef", (0.2, 0.6, 0.1), m(box((0.01, -0.05, 0.8), (0.25, 0.05, 0.805)))),
          ("Pepper_frt1", (0.8, 0.08, 0.05), m(cube((0.06, 0, 0.5), 0.08) + cube((-0.06, 0, 0.65), 0.08))),
          ("Pepper_frt0", (0.6, 0.7, 0.1), m(cube((0.0, -0.06, 0.35), 0.07)))]
o = ['<?xml version="1.0"?>', '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">',
     '<asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset><library_effects>']
for n, c, _ in groups:
    o.append(f'<effect id="e{n}"><profile_COMMON><technique sid="t"><lambert><diffuse><color>{c[0]} {c[1]} {c[2]} 1</color>'
             '</diffuse></lambert></technique></profile_COMMON></effect>')
o.append('</library_effects><library_materials>')
for n, _, _ in groups:
    o.append(f'<material id="m{n}" name="{n}"><instance_effect url="#e{n}"/></material>')
o.append('</library_materials><library_geometries><geometry id="g"><mesh>')
pts = [x for _, _, t in groups for tri in t for p in tri for x in p]
o.append(f'<source id="p"><float_array id="pa" count="{len(pts)}">{" ".join(map(repr, pts))}</float_array>'
         f'<technique_common><accessor source="#pa" count="{len(pts) // 3}" stride="3"><param name="X" type="float"/>'
         '<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>'
         '<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>')
k = 0
for n, _, t in groups:
    o.append(f'<triangles material="{n}" count="{len(t)}"><input semantic="VERTEX" source="#v" offset="0"/><p>'
             + " ".join(str(i) for i in range(k, k + 3 * len(t))) + '</p></triangles>')
    k += 3 * len(t)
o.append(f'</mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s"><node id="n" name="n">'
         f'<matrix>{inch} 0 0 0 0 {inch} 0 0 0 0 {inch} 0 0 0 0 1</matrix><instance_geometry url="#g"><bind_material>'
         '<technique_common>' + "".join(f'<instance_material symbol="{n}" target="#m{n}"/>' for n, _, _ in groups) +
         '</technique_common></bind_material></instance_geometry></node></visual_scene></library_visual_scenes>'
         '<scene><instance_visual_scene url="#s"/></scene></COLLADA>')
open(f"{tmp}/pepper.dae", "w").write("\n".join(o))
PY

# Import with the capsicum preset.
log="$tmp/import.log"
if ! "$canopy" import-plant "$tmp/pepper.dae" --preset capsicum --out "$tmp/plants/pepper" 2>"$log"; then
  fail "import-plant failed: $(cat "$log")"
fi
for f in plant.yaml fruits.json fruit_points.csv meshes/fruit_0.obj meshes/fruit_1.obj meshes/fruit_2.obj; do
  [[ -f "$tmp/plants/pepper/$f" ]] || fail "missing $f"
done
grep -q "size 0.350 x 0.145 x 1.000 m (height 1.000 m, reach 0.255 m from the base); 60 triangles in" "$log" || fail "import report lacks the plant size: $(cat "$log")"
grep -q "fruit (unripe): 12 triangles" "$log" || fail "import report lacks the unripe fruit's triangles"
grep -q "fruit: 24 triangles" "$log" || fail "import report lacks the ripe fruits' triangles"
python3 - "$tmp/plants/pepper/fruits.json" <<'PY' || fail "fruits.json"
import json, sys
f = json.load(open(sys.argv[1]))["fruits"]
assert len(f) == 3, f
assert [x["target"] for x in f] == [False, True, True], [x["target"] for x in f]  # frt0 first (by material name)
PY

# A world mixing it (row 0) with a procedural plant (row 1).
cat > "$tmp/mixed.yaml" <<EOF2
name: mixed
seed: 3
rows: {rows: 2, plants_per_row: 1, position_jitter_m: 0.0}
plant: {height_m: [1.0, 1.1], fruits: [4, 5], fruit_colors: {red: 1.0, green: 0.0}}
plants:
  - {plant: {import: $tmp/plants/pepper}, slot: [0, 0], yaw_deg: 30}
EOF2
"$canopy" world --world "$tmp/mixed.yaml" --out "$tmp/world" 2>"$tmp/world.log" || fail "world: $(cat "$tmp/world.log")"
python3 - "$tmp/world" <<'PY' || fail "world.json / fruits.json of the mixed world"
import json, sys
w = json.load(open(sys.argv[1] + "/world.json"))
assert w["plants"] == 2, w["plants"]
assert w["plant_list"][0]["fruits"] == 3, w["plant_list"][0]
assert w["plant_list"][1]["fruits"] >= 4, w["plant_list"][1]
fr = json.load(open(sys.argv[1] + "/fruits.json"))["fruits"]
assert sorted(f["instance_id"] for f in fr) == list(range(len(fr)))
assert sum(1 for f in fr if not f["target"]) == 1
PY
grep -q 'p0_fruit_0' "$tmp/world/scene.xml" || fail "scene.xml lacks the imported fruit geoms"

# Map it end to end from ring views with renderer labels.
if ! "$canopy" map --world "$tmp/mixed.yaml" --views ring --seg truth --out "$tmp/map" >"$tmp/map.log" 2>&1; then
  fail "map: $(tail -3 "$tmp/map.log")"
fi
python3 - "$tmp/map/metrics.json" <<'PY' || fail "map metrics: $(tail -2 "$tmp/map.log")"
import json, sys
j = json.load(open(sys.argv[1]))
last = j["history"][-1] if "history" in j else j
assert last["coverage"] > 0.3, last["coverage"]
print("mixed world mapped: coverage %.3f" % last["coverage"])
PY

# Bad input: exit 2, one line, no folder left.
expect_error() {  # expect_error "<fragment>" args...
  local fragment="$1"; shift
  local out="$tmp/bad"
  rm -rf "$out" "$out.partial"
  local msg
  msg=$("$canopy" import-plant "$@" --out "$out" 2>&1 >/dev/null)
  local code=$?
  [[ $code -eq 2 ]] || fail "exit $code (want 2) for: $*"
  [[ "$msg" == *"$fragment"* ]] || fail "message '$msg' lacks '$fragment' for: $*"
  [[ $(printf '%s\n' "$msg" | wc -l) -eq 1 ]] || fail "message of more than one line for: $*"
  [[ ! -e "$out" && ! -e "$out.partial" ]] || fail "plant folder left behind for: $*"
}
printf 'not a model' > "$tmp/junk.dae"
printf '# no faces\nv 0 0 0\n' > "$tmp/empty.obj"
expect_error "no such file" "$tmp/missing.dae" --preset capsicum
expect_error "assimp cannot read it" "$tmp/junk.dae" --preset capsicum
expect_error "empty.obj" "$tmp/empty.obj" --preset capsicum
expect_error "no --class rule matches the material(s) 'Pepper_brn'" "$tmp/pepper.dae" --class fruit=frt --class leaf=lef
expect_error "no material maps to the fruit class" "$tmp/pepper.dae" --class default=leaf
expect_error "does not compile" "$tmp/pepper.dae" --class 'fruit=frt[' --preset capsicum
expect_error "--unit-scale" "$tmp/pepper.dae" --preset capsicum --unit-scale 0
expect_error "--unit-scale" "$tmp/pepper.dae" --preset capsicum --unit-scale -1
expect_error "--max-triangles is 40" "$tmp/pepper.dae" --preset capsicum --max-triangles 40
expect_error "unknown preset" "$tmp/pepper.dae" --preset tomato

# glTF 2.0 (Y-up by the format): two octahedron fruits (frt1) and a leaf, written here with an
# embedded buffer; the plant must stand upright (fruit centres at z 0.5 and 0.6 m above the
# lowest point) with two fruit instances.
python3 - "$tmp/plant.gltf" <<'PY'
import base64, json, struct, sys
buf = b""; views = []; accs = []
def add(v, f):
    global buf
    off = len(buf); pos = b"".join(struct.pack("<3f", *p) for p in v); buf += pos
    views.append({"buffer": 0, "byteOffset": off, "byteLength": len(pos)})
    accs.append({"bufferView": len(views) - 1, "componentType": 5126, "count": len(v), "type": "VEC3",
                 "min": [min(p[i] for p in v) for i in range(3)], "max": [max(p[i] for p in v) for i in range(3)]})
    off = len(buf); idx = b"".join(struct.pack("<3H", *t) for t in f); buf += idx
    while len(buf) % 4: buf += b"\0"
    views.append({"buffer": 0, "byteOffset": off, "byteLength": len(idx)})
    accs.append({"bufferView": len(views) - 1, "componentType": 5123, "count": 3 * len(f), "type": "SCALAR"})
    return {"attributes": {"POSITION": len(accs) - 2}, "indices": len(accs) - 1}
def octa(c, r):
    v = [(c[0] + r, c[1], c[2]), (c[0] - r, c[1], c[2]), (c[0], c[1] + r, c[2]), (c[0], c[1] - r, c[2]),
         (c[0], c[1], c[2] + r), (c[0], c[1], c[2] - r)]
    return v, [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
prims = [dict(add(*octa((0.0, 0.5, 0.0), 0.035)), material=0), dict(add(*octa((0.1, 0.6, 0.0), 0.03)), material=0),
         dict(add([(-0.1, 0.3, -0.1), (0.1, 0.3, -0.1), (0.1, 0.3, 0.1), (0, 0, 0), (0.01, 0, 0)],
                  [(0, 1, 2), (3, 4, 0)]), material=1)]
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "meshes": [{"primitives": prims}],
     "materials": [{"name": "frt1_red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1]}},
                   {"name": "lef_green", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.6, 0.1, 1]}}],
     "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
     "bufferViews": views, "accessors": accs}
json.dump(g, open(sys.argv[1], "w"))
PY
"$canopy" import-plant "$tmp/plant.gltf" --preset capsicum --out "$tmp/gltf_plant" >/dev/null 2>&1 || fail "glTF import"
python3 - "$tmp/gltf_plant/fruits.json" <<'PY' || fail "glTF plant: wrong fruits"
import json, sys
f = json.load(open(sys.argv[1]))["fruits"]
assert len(f) == 2, len(f)
z = sorted(round(x["center"][2], 3) for x in f)
assert abs(z[0] - 0.5) < 0.005 and abs(z[1] - 0.6) < 0.005, z
assert all(x["target"] for x in f)
PY

if ((failures > 0)); then
  echo "$failures failure(s)"
  exit 1
fi
echo "import-plant: all checks passed"
