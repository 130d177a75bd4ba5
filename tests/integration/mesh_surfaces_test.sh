#!/usr/bin/env bash
# Surfaces given as meshes against the real server: an irregular
# triangulation of half a cylinder, uploaded as OBJ, flattens (POST
# /v1/surfaces, kind "mesh") to its development; its sheet lists the flat
# triangles and its SVG draws them; a plate deformed along it matches the
# plate deformed along the analytic half cylinder within the triangulation's
# chordal error, and its GLB passes the Khronos validator; a closed mesh, a
# mesh with a hole, one past the vertex limit and an unknown model id are
# refused with what to do.
# Usage: mesh_surfaces_test.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
gltf="$here/../gltf"
source "$here/launch_server.sh"
serve_for_test "$1" --answer-cache-mib 0 --max-surface-mesh-vertices 5000 \
  --max-surface-mesh-pairs 20000

# OBJ writers: half a cylinder of radius 1 and height 2 as a jittered
# CELLS x CELLS grid of triangles, optionally with a hole (one cell left out);
# with RADIUS, the same triangulation bent to that radius (its arcs as long).
cylinder_obj() {  # FILE CELLS [hole|whole] [RADIUS]
  python3 - "$@" << 'PY'
import math, random, sys
path, cells = sys.argv[1], int(sys.argv[2])
hole = len(sys.argv) > 3 and sys.argv[3] == "hole"
radius = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0
random.seed(7)
n = cells + 1
with open(path, "w") as f:
    for j in range(n):
        for i in range(n):
            s, t = i / cells, j / cells
            if 0 < i < cells: s += random.uniform(-0.3, 0.3) / cells
            if 0 < j < cells: t += random.uniform(-0.3, 0.3) / cells
            a = math.pi * s / radius
            f.write("v %.17g %.17g %.17g\n" % (radius * math.cos(a), radius * math.sin(a), 2 * t))
    for j in range(cells):
        for i in range(cells):
            if hole and i == cells // 2 and j == cells // 2: continue
            a, b, c, d = 1 + i + n * j, 2 + i + n * j, 2 + i + n * (j + 1), 1 + i + n * (j + 1)
            f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
PY
}
upload() {  # FILE -> prints the model id
  curl -sS -f -F mesh=@"$1" "$base/v1/models" |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])'
}
surface() {  # NAME MODEL_ID -> prints the status; the body in $out/NAME.json
  curl -sS -o "$out/$1.json" -w '%{http_code}' -H 'Content-Type: application/json' \
    -d "{\"surface\":{\"kind\":\"mesh\",\"model_id\":\"$2\"},\"sampling\":{\"nu\":33,\"nv\":33}}" \
    "$base/v1/surfaces"
}

cylinder_obj "$out/half.obj" 24
half=$(upload "$out/half.obj")
status=$(surface half "$half")
[[ $status == 200 || $status == 201 ]] || fail "the mesh surface: $status $(cat "$out/half.json")"
python3 - "$out/half.json" << 'PY' || fail "the mesh surface's summary"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["method"] == "majorization", s
m = s["mesh"]
assert m["vertices"] == 625 and m["triangles"] == 1152 and m["boundary_vertices"] == 96, m
assert m["welded"] == 0 and m["pairs"] > 625 * 6, m
q = s["quality"]
assert q["stress"] < 1e-3 and q["folded_cells"] == 0, q
PY
id=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["id"])' "$out/half.json")
# The sheet: the flat triangles, their layout the development (pi x 2) to
# within the triangulation's error.
curl -sS -f -o "$out/sheet.json" "$base/v1/surfaces/$id"
python3 - "$out/sheet.json" << 'PY' || fail "the mesh surface's flat triangles"
import json, math, sys
s = json.load(open(sys.argv[1]))
flat, tris = s["mesh"]["flat"], s["mesh"]["triangles"]
assert len(flat) == 625 and len(tris) == 1152
area = 0.0
for a, b, c in tris:
    (ax, ay), (bx, by), (cx, cy) = flat[a], flat[b], flat[c]
    cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    assert cross > 0, "a folded or clockwise triangle"
    area += cross / 2
# The triangulation is inscribed: its area is the development's (2 pi) less
# the chords' (sin x / x, x the half angle of a cell, about 1 - 1.6e-3).
assert abs(area / (2 * math.pi) - 1) < 3e-3, area
xs, ys = [p[0] for p in flat], [p[1] for p in flat]
extent = sorted([max(xs) - min(xs), max(ys) - min(ys)])
assert abs(extent[1] - math.pi) < 0.01 and abs(extent[0] - 2) < 0.01, extent
PY
curl -sS -f -o "$out/flat.svg" "$base/v1/surfaces/$id/flat.svg"
[[ $(grep -c '<polygon points="[^"]*" fill="[^"]*"><title>triangle' "$out/flat.svg") == 1152 ]] ||
  fail "the SVG does not draw the 1152 flat triangles"

# A plate along the mesh and along the analytic half cylinder.
python3 - "$out/plate.obj" << 'PY'
import sys
x, y, z = 1.0, 0.5, 0.05
with open(sys.argv[1], "w") as f:
    for p in [(-x, -y, -z), (x, -y, -z), (x, y, -z), (-x, y, -z),
              (-x, -y, z), (x, -y, z), (x, y, z), (-x, y, z)]:
        f.write("v %g %g %g\n" % p)
    for t in [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5),
              (2, 3, 7), (2, 7, 6), (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]:
        f.write("f %d %d %d\n" % t)
PY
deform() {  # NAME SURFACE_JSON
  curl -sS -o "$out/$1.glb" -w '%{http_code}' -F mesh=@"$out/plate.obj" \
    -F "params={\"surface\":$2,\"sampling\":{\"nu\":33,\"nv\":33},\"subdivision\":{\"mode\":\"off\"},\"output\":{\"format\":\"glb_plain\"}}" \
    "$base/v1/deform"
}
status=$(deform on-mesh "{\"kind\":\"mesh\",\"model_id\":\"$half\"}")
[[ $status == 200 ]] || fail "the plate along the mesh: $status $(cat "$out/on-mesh.glb")"
status=$(deform on-cylinder '{"kind":"cylinder","radius":1,"height":2,"angle_deg":180}')
[[ $status == 200 ]] || fail "the plate along the cylinder: $status"
# Twice the sagitta of the longest edges (1.6 cells of pi / 24): 0.0087.
python3 "$gltf/glb_positions.py" nearest "$out/on-mesh.glb" "$out/on-cylinder.glb" 0.0087 ||
  fail "the plate along the mesh is not the plate along the cylinder"
node "$gltf/validate.mjs" "$out/on-mesh.glb"

# An animation whose keyframes are meshes (a cloth bending): the half
# cylinder at time 0, the same triangulation bent to radius 1.5 at time 1.
cylinder_obj "$out/bent.obj" 24 whole 1.5
bent=$(upload "$out/bent.obj")
python3 - "$half" "$bent" "$out" << 'PY'
import json, sys
half, bent, out = sys.argv[1:4]
key = lambda t, m: {"time": t, "surface": {"kind": "mesh", "model_id": m}}
anim = {"keyframes": [key(0, half), key(1, bent)], "interpolation": "linear", "frames": 5, "fps": 10}
common = {"animation": anim, "sampling": {"nu": 33, "nv": 33}, "subdivision": {"mode": "off"}}
json.dump(dict(common, output={"compression": "meshopt"}), open(out + "/mesh-anim.json", "w"))
json.dump(dict(common, output={"compression": "none"}), open(out + "/mesh-anim-plain.json", "w"))
for k in (0, 2, 4):
    json.dump(dict(common, frame=k, output={"format": "glb_plain"}), open(out + "/mesh-frame%d.json" % k, "w"))
other = json.loads(json.dumps(common))
other["animation"]["keyframes"][1]["surface"]["model_id"] = "OTHER"
json.dump(other, open(out + "/mesh-anim-other.json", "w"))
unknown = json.loads(json.dumps(common))
unknown["animation"]["keyframes"][1]["surface"]["model_id"] = "0123456789abcdef0123456789abcdef"
json.dump(unknown, open(out + "/mesh-anim-unknown.json", "w"))
PY
curl -sS -f -o "$out/mesh-anim.glb" -D "$out/mesh-anim-headers.txt" -F mesh=@"$out/plate.obj" \
  -F "params=<$out/mesh-anim.json" "$base/v1/animate" || fail "the mesh animation"
grep -qi '^x-surfdeform-stats: .*"frames":5' "$out/mesh-anim-headers.txt" || fail "mesh animation: frames"
curl -sS -f -o "$out/mesh-anim-plain.glb" -F mesh=@"$out/plate.obj" \
  -F "params=<$out/mesh-anim-plain.json" "$base/v1/animate" || fail "the mesh animation, plain"
for k in 0 2 4; do
  curl -sS -f -o "$out/mesh-frame$k.glb" -F mesh=@"$out/plate.obj" \
    -F "params=<$out/mesh-frame$k.json" "$base/v1/deform" || fail "mesh animation frame $k"
done
node "$gltf/validate.mjs" "$out/mesh-anim-plain.glb"
node "$gltf/check_animation.mjs" "$out/mesh-anim.glb" "$out/mesh-anim-plain.glb" 10 \
  0 "$out/mesh-frame0.glb" 2 "$out/mesh-frame2.glb" 4 "$out/mesh-frame4.glb"
# Frame 0 is the plate along the first mesh alone; frame 4 lies along the
# analytic cylinder of the last key as the plate along the first lies along
# its own (the sheet stayed where it was).
python3 "$gltf/glb_positions.py" compare "$out/mesh-frame0.glb" "$out/on-mesh.glb" 0 ||
  fail "the animation's frame 0 is not the plate along the first mesh"
status=$(deform on-bent-cylinder '{"kind":"cylinder","radius":1.5,"height":2,"angle_deg":120}')
[[ $status == 200 ]] || fail "the plate along the bent cylinder: $status"
python3 "$gltf/glb_positions.py" nearest "$out/mesh-frame4.glb" "$out/on-bent-cylinder.glb" 0.0087 ||
  fail "the animation's last frame is not the plate along the bent cylinder"
# Keys that are not one mesh, and a key whose mesh is unknown.
cylinder_obj "$out/coarse.obj" 12
coarse=$(upload "$out/coarse.obj")
sed -i "s/OTHER/$coarse/" "$out/mesh-anim-other.json"
animate_refused() {  # NAME STATUS FIELD TEXT
  curl -sS -o "$out/$1.out" -w '%{http_code}' -F mesh=@"$out/plate.obj" \
    -F "params=<$out/$1.json" "$base/v1/animate" > "$out/$1.status"
  python3 - "$out/$1.out" "$(cat "$out/$1.status")" "$2" "$3" "$4" << 'PY' ||
import json, sys
body = json.load(open(sys.argv[1]))
assert sys.argv[2] == sys.argv[3] and str(body["status"]) == sys.argv[3], body
assert body["field"] == sys.argv[4], body
assert sys.argv[5] in body["detail"], body
PY
    fail "$1: expected $2 at $3 saying \"$4\": $(cat "$out/$1.out")"
}
animate_refused mesh-anim-other 422 animation.keyframes[1].surface.model_id \
  "is a mesh of 169 vertices and 288 triangles (after welding) but keyframe 0's has 625 and 1152"
animate_refused mesh-anim-unknown 404 animation.keyframes[1].surface.model_id \
  "POST the mesh to /v1/models again"

# Refusals.
refused() {  # NAME STATUS TEXT
  python3 - "$out/$1.json" "$2" "$3" "$4" << 'PY' || fail "$1: expected $2 saying \"$3\", got $4: $(cat "$out/$1.json")"
import json, sys
body = json.load(open(sys.argv[1]))
assert str(body["status"]) == sys.argv[2] == sys.argv[4], body
assert sys.argv[3] in body["detail"], body
assert body["field"].startswith("surface"), body
PY
}
python3 - "$out/tetra.obj" << 'PY'
import sys
open(sys.argv[1], "w").write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")
PY
status=$(surface tetra "$(upload "$out/tetra.obj")")
refused tetra 422 "the mesh is closed" "$status"
cylinder_obj "$out/holed.obj" 8 hole
status=$(surface holed "$(upload "$out/holed.obj")")
refused holed 422 "1 hole besides its outer boundary" "$status"
cylinder_obj "$out/large.obj" 80
status=$(surface large "$(upload "$out/large.obj")")
refused large 413 "6561 vertices, more than 5000" "$status"
# Range 6 on the half cylinder: some 39k vertex pairs, more than 20000.
curl -sS -o "$out/wide.json" -w '%{http_code}' -H 'Content-Type: application/json' \
  -d "{\"surface\":{\"kind\":\"mesh\",\"model_id\":\"$half\"},\"flatten\":{\"range\":6}}" \
  "$base/v1/surfaces" > "$out/wide.status"
python3 - "$out/wide.json" "$(cat "$out/wide.status")" << 'PY' || fail "range 6: $(cat "$out/wide.json")"
import json, sys
body = json.load(open(sys.argv[1]))
assert sys.argv[2] == "413" and body["status"] == 413, body
assert body["field"] == "flatten.range" and body["limit"] == 20000, body
assert "more than 20000 vertex pairs within 6 rings" in body["detail"], body
PY
status=$(surface unknown 0123456789abcdef0123456789abcdef)
refused unknown 404 "POST the mesh to /v1/models again" "$status"
stop_served_server
echo "mesh surfaces: ok"
