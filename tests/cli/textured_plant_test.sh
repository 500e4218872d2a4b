#!/usr/bin/env bash
# Textured plant models end to end, on files the test writes itself: a COLLADA plant whose
# materials are white with their colour in TGA textures (red ripe fruit, yellow unripe fruit,
# green leaves and stem), as the community's capsicum models are. It imports with its
# textures (and with --texture mean), its world renders it, and canopy map with ring views
# reaches fruit SC >= 0.8 under colour segmentation. A plant whose fruit texture is green
# triggers the colour check's warning, --strict refuses it, and canopy world refuses a world
# of it under --seg color. A glTF plant with an embedded PNG texture imports textured.
# Usage: textured_plant_test.sh canopy
set -u
canopy="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

python3 - "$tmp" <<'PY'
import struct, sys
tmp = sys.argv[1]
def box(lo, hi):
    v = lambda i: ((hi if i & 1 else lo)[0], (hi if i & 2 else lo)[1], (hi if i & 4 else lo)[2])
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    out = []
    for a, b, c, d in quads:
        out += [(v(a), v(b), v(c)), (v(a), v(c), v(d))]
    return out
def cube(c, s):
    return box([x - s / 2 for x in c], [x + s / 2 for x in c])
# Every quad's two triangles span the whole texture.
quad_uv = [((0, 0), (1, 0), (1, 1)), ((0, 0), (1, 1), (0, 1))]
groups = [("Pepper_brn", box((-0.01, -0.01, 0), (0.01, 0.01, 1.0))),
          ("Pepper_lef", box((0.01, -0.05, 0.8), (0.25, 0.05, 0.805))),
          ("Pepper_frt1", cube((0.07, 0, 0.5), 0.08) + cube((-0.07, 0, 0.65), 0.08)),
          ("Pepper_frt0", cube((0.0, -0.07, 0.35), 0.07))]
def tga(path, w, h, colour):  # uncompressed 24-bit, origin top left; a two-tone checker of `colour`
    data = bytearray([0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, w & 255, w >> 8, h & 255, h >> 8, 24, 0x20])
    for y in range(h):
        for x in range(w):
            k = 0.85 if (x // 4 + y // 4) % 2 else 1.0
            r, g, b = (int(c * k) for c in colour)
            data += bytes([b, g, r])
    open(path, "wb").write(data)
def write(name, fruit_colour):
    d = f"{tmp}/{name}"
    import os
    os.makedirs(d, exist_ok=True)
    colours = {"Pepper_brn": (60, 150, 50), "Pepper_lef": (40, 170, 45), "Pepper_frt1": fruit_colour,
               "Pepper_frt0": (200, 190, 40)}
    for n, _ in groups:
        tga(f"{d}/{n}.tga", 16, 16, colours[n])
    o = ['<?xml version="1.0"?>', '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">',
         '<asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset><library_images>']
    for n, _ in groups:
        o.append(f'<image id="i{n}" name="i{n}"><init_from>{n}.tga</init_from></image>')
    o.append('</library_images><library_effects>')
    for n, _ in groups:
        o.append(f'<effect id="e{n}"><profile_COMMON><newparam sid="s{n}"><surface type="2D"><init_from>i{n}</init_from>'
                 f'</surface></newparam><newparam sid="t{n}"><sampler2D><source>s{n}</source></sampler2D></newparam>'
                 f'<technique sid="t"><lambert><diffuse><texture texture="t{n}" texcoord="UV"/></diffuse></lambert>'
                 '</technique></profile_COMMON></effect>')
    o.append('</library_effects><library_materials>')
    for n, _ in groups:
        o.append(f'<material id="m{n}" name="{n}"><instance_effect url="#e{n}"/></material>')
    o.append('</library_materials><library_geometries><geometry id="g"><mesh>')
    pts = [x for _, t in groups for tri in t for p in tri for x in p]
    uvs = [x for _, t in groups for i, tri in enumerate(t) for c in quad_uv[i % 2] for x in c]
    o.append(f'<source id="p"><float_array id="pa" count="{len(pts)}">{" ".join(map(repr, pts))}</float_array>'
             f'<technique_common><accessor source="#pa" count="{len(pts) // 3}" stride="3"><param name="X" type="float"/>'
             '<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>'
             f'<source id="u"><float_array id="ua" count="{len(uvs)}">{" ".join(map(repr, uvs))}</float_array>'
             f'<technique_common><accessor source="#ua" count="{len(uvs) // 2}" stride="2"><param name="S" type="float"/>'
             '<param name="T" type="float"/></accessor></technique_common></source>'
             '<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>')
    k = 0
    for n, t in groups:
        o.append(f'<triangles material="{n}" count="{len(t)}"><input semantic="VERTEX" source="#v" offset="0"/>'
                 '<input semantic="TEXCOORD" source="#u" offset="1" set="0"/><p>'
                 + " ".join(f"{i} {i}" for i in range(k, k + 3 * len(t))) + '</p></triangles>')
        k += 3 * len(t)
    o.append('</mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s"><node id="n" name="n">'
             '<instance_geometry url="#g"><bind_material><technique_common>' +
             "".join(f'<instance_material symbol="{n}" target="#m{n}"><bind_vertex_input semantic="UV" '
                     'input_semantic="TEXCOORD" input_set="0"/></instance_material>' for n, _ in groups) +
             '</technique_common></bind_material></instance_geometry></node></visual_scene></library_visual_scenes>'
             '<scene><instance_visual_scene url="#s"/></scene></COLLADA>')
    open(f"{d}/pepper.dae", "w").write("\n".join(o))
write("red", (210, 35, 25))
write("green", (60, 170, 40))
PY

world_of() {  # world_of NAME PLANT_FOLDER: one row, one plant
  cat > "$tmp/$1.yaml" <<EOF2
name: $1
seed: 3
rows: {rows: 1, plants_per_row: 1, position_jitter_m: 0.0}
plants:
  - {plant: {import: $2}, slot: [0, 0]}
EOF2
}
map_coverage() {  # map_coverage WORLD OUT: prints the final fruit SC of ring views under colour segmentation
  "$canopy" map --world "$tmp/$1.yaml" --views ring --seg color --out "$tmp/$2" >"$tmp/$2.log" 2>&1 || {
    echo "map failed: $(tail -2 "$tmp/$2.log")" >&2; echo 0; return; }
  python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); print((j["history"][-1] if "history" in j else j)["coverage"])' \
    "$tmp/$2/metrics.json"
}

# 1. Textured import: every material rendered with its texture, the colour check in the log.
log="$tmp/import.log"
"$canopy" import-plant "$tmp/red/pepper.dae" --preset capsicum --out "$tmp/plants/red" >"$log" 2>&1 ||
  fail "textured import failed: $(cat "$log")"
grep -q "material 'Pepper_frt1' (fruit, .*colour image (texture Pepper_frt1.tga, 16 x 16 px).*colour segmentation: fruit 1.00" "$log" ||
  fail "the import log lacks the textured fruit material's colour check: $(grep Pepper_frt1 "$log")"
grep -q "COLOUR CHECK" "$log" && fail "a warning for the red plant: $(grep 'COLOUR CHECK' "$log")"
ls "$tmp"/plants/red/textures/*.png >/dev/null 2>&1 || fail "no textures/*.png in the plant folder"
grep -q "^vt " "$tmp/plants/red/meshes/fruit_1.obj" || fail "fruit mesh without texture coordinates"
world_of red "$tmp/plants/red"
"$canopy" world --world "$tmp/red.yaml" --out "$tmp/world_red" >"$tmp/world_red.log" 2>&1 || fail "world: $(cat "$tmp/world_red.log")"
grep -q 'file="textures/plant_tex_0.png"' "$tmp/world_red/scene.xml" || fail "scene.xml names no texture file"
[[ -f "$tmp/world_red/textures/plant_tex_0.png" ]] || fail "canopy world did not copy the textures beside scene.xml"
cov=$(map_coverage red map_red)
echo "textured plant, ring views, colour segmentation: fruit SC $cov"
python3 -c "import sys; sys.exit(0 if float('$cov') >= 0.8 else 1)" || fail "textured plant: fruit SC $cov < 0.8"

# 2. --texture mean: flat colours, no textures, the same map quality.
"$canopy" import-plant "$tmp/red/pepper.dae" --preset capsicum --texture mean --out "$tmp/plants/red_mean" >"$tmp/mean.log" 2>&1 ||
  fail "--texture mean import failed: $(cat "$tmp/mean.log")"
grep -q "material 'Pepper_frt1' (fruit, .*colour mean (texture Pepper_frt1.tga" "$tmp/mean.log" || fail "--texture mean not reported"
[[ ! -e "$tmp/plants/red_mean/textures" ]] || fail "--texture mean wrote textures"
grep -q "^vt " "$tmp/plants/red_mean/meshes/fruit_1.obj" && fail "--texture mean wrote texture coordinates"
world_of red_mean "$tmp/plants/red_mean"
cov=$(map_coverage red_mean map_red_mean)
echo "--texture mean plant, ring views, colour segmentation: fruit SC $cov"
python3 -c "import sys; sys.exit(0 if float('$cov') >= 0.8 else 1)" || fail "--texture mean plant: fruit SC $cov < 0.8"

# 3. A green ripe-fruit texture: a loud warning, --strict refuses it, canopy world refuses its world under colour.
"$canopy" import-plant "$tmp/green/pepper.dae" --preset capsicum --out "$tmp/plants/green" >"$tmp/green.log" 2>&1 ||
  fail "green import failed: $(cat "$tmp/green.log")"
grep -q "COLOUR CHECK: material 'Pepper_frt1': target fruit material, but colour segmentation labels only 0% of its texture 'fruit'" "$tmp/green.log" ||
  fail "no colour-check warning for the green fruit: $(cat "$tmp/green.log")"
msg=$("$canopy" import-plant "$tmp/green/pepper.dae" --preset capsicum --strict --out "$tmp/plants/green_strict" 2>&1 >/dev/null)
code=$?
[[ $code -eq 2 ]] || fail "--strict exit $code (want 2)"
[[ "$msg" == *"material 'Pepper_frt1'"*"(--strict)"* ]] || fail "--strict message: $msg"
[[ $(printf '%s\n' "$msg" | wc -l) -eq 1 ]] || fail "--strict message of more than one line: $msg"
[[ ! -e "$tmp/plants/green_strict" ]] || fail "--strict left a plant folder"
world_of green "$tmp/plants/green"
msg=$("$canopy" world --world "$tmp/green.yaml" --seg color --out "$tmp/world_green" 2>&1 >/dev/null)
code=$?
[[ $code -eq 2 ]] || fail "canopy world --seg color on the green plant: exit $code (want 2)"
[[ "$msg" == *"plants/green: material 'Pepper_frt1'"* ]] || fail "canopy world message names no plant and material: $msg"
[[ ! -e "$tmp/world_green" ]] || fail "canopy world left a folder"
"$canopy" world --world "$tmp/green.yaml" --seg truth --out "$tmp/world_green" >"$tmp/world_green.log" 2>&1 ||
  fail "canopy world --seg truth refused the green plant: $(cat "$tmp/world_green.log")"
grep -q "material 'Pepper_frt1'" "$tmp/world_green.log" || fail "canopy world --seg truth does not warn about the green fruit"

# 4. glTF with an embedded PNG texture (a data URI): red fruit, green leaf.
python3 - "$tmp/plant.gltf" <<'PY'
import base64, json, struct, sys, zlib
def png(w, h, rgb):
    raw = b"".join(b"\0" + bytes(rgb) * w for _ in range(h))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
buf = b""; views = []; accs = []
def view(data):
    global buf
    off = len(buf); buf += data
    while len(buf) % 4: buf += b"\0"
    views.append({"buffer": 0, "byteOffset": off, "byteLength": len(data)})
    return len(views) - 1
def prim(v, f, material):
    p = view(b"".join(struct.pack("<3f", *x) for x in v))
    accs.append({"bufferView": p, "componentType": 5126, "count": len(v), "type": "VEC3",
                 "min": [min(x[i] for x in v) for i in range(3)], "max": [max(x[i] for x in v) for i in range(3)]})
    t = view(b"".join(struct.pack("<2f", (x[0] * 7) % 1.0, (x[2] * 5) % 1.0) for x in v))
    accs.append({"bufferView": t, "componentType": 5126, "count": len(v), "type": "VEC2"})
    i = view(b"".join(struct.pack("<3H", *x) for x in f))
    accs.append({"bufferView": i, "componentType": 5123, "count": 3 * len(f), "type": "SCALAR"})
    return {"attributes": {"POSITION": len(accs) - 3, "TEXCOORD_0": len(accs) - 2}, "indices": len(accs) - 1,
            "material": material}
def octa(c, r):
    v = [(c[0] + r, c[1], c[2]), (c[0] - r, c[1], c[2]), (c[0], c[1] + r, c[2]), (c[0], c[1] - r, c[2]),
         (c[0], c[1], c[2] + r), (c[0], c[1], c[2] - r)]
    return v, [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
prims = [prim(*octa((0.0, 0.5, 0.0), 0.035), 0), prim(*octa((0.1, 0.6, 0.0), 0.03), 0),
         prim([(-0.1, 0.3, -0.1), (0.1, 0.3, -0.1), (0.1, 0.3, 0.1), (0, 0, 0), (0.01, 0, 0)], [(0, 1, 2), (3, 4, 0)], 1)]
images = [view(png(8, 8, (205, 30, 25))), view(png(8, 8, (40, 165, 45)))]
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "meshes": [{"primitives": prims}],
     "images": [{"bufferView": images[0], "mimeType": "image/png"}, {"bufferView": images[1], "mimeType": "image/png"}],
     "textures": [{"source": 0}, {"source": 1}],
     "materials": [{"name": "frt1_red", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                   {"name": "lef_green", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}],
     "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
     "bufferViews": views, "accessors": accs}
json.dump(g, open(sys.argv[1], "w"))
PY
"$canopy" import-plant "$tmp/plant.gltf" --preset capsicum --out "$tmp/plants/gltf" >"$tmp/gltf.log" 2>&1 ||
  fail "glTF import failed: $(cat "$tmp/gltf.log")"
grep -q "material 'frt1_red' (fruit, .*colour image (texture \*0, 8 x 8 px), mean rgb 0.80 0.12 0.10; colour segmentation: fruit 1.00" "$tmp/gltf.log" ||
  fail "glTF embedded texture not used: $(grep frt1_red "$tmp/gltf.log")"
ls "$tmp"/plants/gltf/textures/*.png >/dev/null 2>&1 || fail "glTF plant folder has no textures"

if ((failures > 0)); then
  echo "$failures failure(s)"
  exit 1
fi
echo "textured plants: all checks passed"
