#!/usr/bin/env bash
# Closed surfaces against the real server (closed-form sheets):
# a full cylinder's sheet says it is periodic and gives its period; the
# bunny across the seam is the bunny half a turn away, turned; a band longer
# than the circumference goes round with a warning; a cone band across the
# seam deforms; a sphere belt is flattened periodic and a band across its
# seam lies on the sphere; the GLBs across the seam pass the Khronos
# validator; a
# half cylinder still refuses a model off its sheet.
# Usage: closed_surfaces_test.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
data="$here/../../client/web/samples"
gltf="$here/../gltf"
source "$here/launch_server.sh"
serve_for_test "$1" --answer-cache-mib 0

cylinder='{"kind":"cylinder","radius":1,"height":2,"angle_deg":360}'
sampling='{"nu":33,"nv":9}'
# The sheet: periodic in u, its period the translation (2 pi R, 0).
curl -sS -f -o "$out/sheet.json" -H 'Content-Type: application/json' \
  -d "{\"surface\":$cylinder,\"sampling\":$sampling}" "$base/v1/surfaces"
python3 - "$out/sheet.json" << 'PY' || fail "the sheet's period"
import json, math, sys
s = json.load(open(sys.argv[1]))
assert s["periodic_u"] is True, s
assert abs(s["period"]["angle_deg"]) < 1e-9, s["period"]
tx, ty = s["period"]["translation"]
assert abs(tx - 2 * math.pi) < 1e-12 and abs(ty) < 1e-12, s["period"]
PY
id=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["id"])' "$out/sheet.json")
curl -sS -f -o "$out/flat.svg" "$base/v1/surfaces/$id/flat.svg"
[[ $(grep -c '<polyline' "$out/flat.svg") == 2 ]] && grep -q 'class="seam"' "$out/flat.svg" ||
  fail "the sheet's SVG does not draw the seam"
curl -sS -f "$base/v1/info" | grep -q '"closed_surfaces":{"description":"[^"]*","periodic_u":\["cylinder","cone","sphere","torus","bspline","nurbs","grid"\],"periodic_v":\["torus","bspline","nurbs","grid"\]}' ||
  fail "/v1/info does not describe the closed surfaces"

# The bunny across the seam (sheet x = 0) and half a turn away (x = pi R):
# one is the other turned half a turn about the axis, vertex for vertex.
deform() {  # NAME PARAMS_JSON [MESH]
  curl -sS -o "$out/$1.glb" -D "$out/$1-headers.txt" -w '%{http_code}' \
    -F mesh=@"${3:-$data/bunny.ply}" -F "params=$2" "$base/v1/deform"
}
half=$(python3 -c 'import math; print(math.pi)')
for at in 0 "$half"; do
  status=$(deform "bunny-$at" "{\"surface\":$cylinder,\"sampling\":$sampling,
    \"placement\":{\"center\":[$at,1]},\"output\":{\"format\":\"glb_plain\"}}")
  [[ $status == 200 ]] || fail "the bunny at $at: $status $(cat "$out/bunny-$at.glb")"
done
python3 "$gltf/glb_positions.py" compare "$out/bunny-0.glb" "$out/bunny-$half.glb" 1e-6 --half-turn ||
  fail "the bunny across the seam is not the bunny half a turn away, turned"
node "$gltf/validate.mjs" "$out/bunny-0.glb"

# A band 1.2 circumferences long: it goes round, over itself, with a warning.
band() {  # FILE LENGTH: a strip of quads 0.04 high
  python3 - "$1" "$2" << 'PY'
import sys
length, n = float(sys.argv[2]), 60
with open(sys.argv[1], "w") as f:
    for j in range(2):
        for i in range(n + 1):
            f.write("v %.9f %.9f 0\n" % (-length / 2 + length * i / n, -0.02 + 0.04 * j))
    for i in range(n):
        f.write("f %d %d %d %d\n" % (i + 1, i + 2, n + i + 3, n + i + 2))
PY
}
band "$out/long.obj" "$(python3 -c 'import math; print(1.2 * 2 * math.pi)')"
status=$(deform long "{\"surface\":$cylinder,\"sampling\":$sampling,\"placement\":{\"center\":[0,1]}}" \
  "$out/long.obj")
[[ $status == 200 ]] || fail "the long band: $status $(cat "$out/long.glb")"
python3 - "$out/long-headers.txt" << 'PY' || fail "turns: $(cat "$out/long-headers.txt")"
import json, sys
line = next(l for l in open(sys.argv[1]) if l.lower().startswith("x-surfdeform-stats:"))
stats = json.loads(line.split(":", 1)[1])
assert abs(stats["placement"]["turns"] - 1.2) < 1e-6, stats["placement"]
assert any("goes 1.2 times round the closed surface" in w for w in stats["warnings"]), stats
PY

# A full cone: a band across its seam (the sheet's column u = 0 runs from
# the origin along +Y) deforms.
cone='{"kind":"cone","radius_bottom":1,"radius_top":0.5,"height":1,"angle_deg":360}'
band "$out/short.obj" 1.5
status=$(deform cone "{\"surface\":$cone,\"sampling\":$sampling,\"placement\":{\"center\":[0.02,0.5]},
  \"output\":{\"format\":\"glb_plain\",\"distortion\":true}}" "$out/short.obj")
[[ $status == 200 ]] || fail "the cone band across the seam: $status $(cat "$out/cone.glb")"
node "$gltf/validate.mjs" "$out/cone.glb"

# A sphere belt (its whole longitude) is flattened periodic: its sheet has a
# translation period, and a band across its seam deforms onto the sphere
# and passes the validator.
belt='{"kind":"sphere","radius":1,"lon_min_deg":0,"lon_max_deg":360,"lat_min_deg":-40,"lat_max_deg":40}'
curl -sS -f -o "$out/belt.json" -H 'Content-Type: application/json' \
  -d "{\"surface\":$belt,\"sampling\":$sampling}" "$base/v1/surfaces"
python3 - "$out/belt.json" << 'PY' || fail "the belt's period: $(cat "$out/belt.json")"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["periodic_u"] is True and s["method"] == "majorization", s
assert abs(s["period"]["angle_deg"]) < 1e-9, s["period"]
tx, ty = s["period"]["translation"]
assert 5.0 < tx < 6.3 and abs(ty) < 1e-6, s["period"]  # between the waist's and the equator's
PY
status=$(deform belt "{\"surface\":$belt,\"sampling\":$sampling,\"placement\":{\"center\":[0,0.7]},
  \"output\":{\"format\":\"glb_plain\",\"distortion\":true}}" "$out/short.obj")
[[ $status == 200 ]] || fail "the band across the belt's seam: $status $(cat "$out/belt.glb")"
node "$gltf/validate.mjs" "$out/belt.glb"
python3 "$gltf/glb_positions.py" radius "$out/belt.glb" 1.0 1e-6 ||
  fail "the band across the belt's seam is off the sphere"

# A whole torus is a flat torus: periodic both ways, both seams drawn, and
# a band across the corner where they cross deforms onto the torus.
torus='{"kind":"torus","major_radius":3,"minor_radius":1,"u_min_deg":0,"u_max_deg":360,"v_min_deg":0,"v_max_deg":360}'
curl -sS -f -o "$out/torus.json" -H 'Content-Type: application/json' \
  -d "{\"surface\":$torus,\"sampling\":{\"nu\":33,\"nv\":17}}" "$base/v1/surfaces"
python3 - "$out/torus.json" << 'PY' || fail "the flat torus: $(cat "$out/torus.json")"
import json, math, sys
s = json.load(open(sys.argv[1]))
assert s["periodic_u"] is True and s["periodic_v"] is True, s
tu, tv = s["period"]["translation"], s["period_v"]["translation"]
assert 2 * math.pi * 2 < math.hypot(*tu) < 2 * math.pi * 4, tu
assert abs(math.hypot(*tv) - 2 * math.pi) < 0.2 * 2 * math.pi, tv
PY
id=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["id"])' "$out/torus.json")
curl -sS -f -o "$out/torus.svg" "$base/v1/surfaces/$id/flat.svg"
[[ $(grep -c '<polyline' "$out/torus.svg") == 4 ]] || fail "the flat torus's SVG does not draw both seams"
status=$(deform torus "{\"surface\":$torus,\"sampling\":{\"nu\":33,\"nv\":17},
  \"placement\":{\"center\":[0,0]},\"output\":{\"format\":\"glb_plain\"}}" "$out/short.obj")
[[ $status == 200 ]] || fail "the band across the torus's seams: $status $(cat "$out/torus.glb")"
node "$gltf/validate.mjs" "$out/torus.glb"

# The sample bottle (a NURBS surface of revolution, periodic_u) with the
# sample label ("SURFDEFORM", one component per letter) centred on its seam:
# the text goes nearly all round, each letter rigid, and passes the
# validator.
python3 - "$data/bottle.json" "$out/bottle-request.json" << 'PY'
import json, sys
spec = json.load(open(sys.argv[1]))
spec.pop("description")
json.dump({"surface": spec, "sampling": {"nu": 33, "nv": 17}}, open(sys.argv[2], "w"))
PY
curl -sS -f -o "$out/bottle.json" -H 'Content-Type: application/json' \
  -d @"$out/bottle-request.json" "$base/v1/surfaces"
python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); assert s["periodic_u"], s' \
  "$out/bottle.json" || fail "the bottle is not periodic"
surface=$(python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))["surface"]))' \
  "$out/bottle-request.json")
status=$(deform label "{\"surface\":$surface,\"sampling\":{\"nu\":33,\"nv\":17},
  \"placement\":{\"center\":{\"fraction\":[0,0.5]},\"rigid\":\"components\",\"anchor\":\"bottom\"},
  \"output\":{\"format\":\"glb\"}}" "$data/label.obj")
[[ $status == 200 ]] || fail "the label round the bottle: $status $(cat "$out/label.glb")"
node "$gltf/validate.mjs" "$out/label.glb"
python3 - "$out/label-headers.txt" << 'PY' || fail "the label: $(cat "$out/label-headers.txt")"
import json, sys
line = next(l for l in open(sys.argv[1]) if l.lower().startswith("x-surfdeform-stats:"))
stats = json.loads(line.split(":", 1)[1])
assert 0.9 < stats["placement"]["turns"] <= 1.0, stats["placement"]  # 5.85 round a period of ~6.1
assert stats["rigid"]["parts"] == 10, stats.get("rigid")
PY

# A grid declared periodic whose last column is not its first: 422, the gap.
status=$(curl -sS -o "$out/open-grid.json" -w '%{http_code}' -H 'Content-Type: application/json' \
  -d '{"surface":{"kind":"grid","nu":4,"nv":2,"periodic_u":true,"points":[[0,0,0],[1,0,0],[1,1,0],[0,1.5,0],[0,0,1],[1,0,1],[1,1,1],[0,1.5,1]]}}' \
  "$base/v1/surfaces")
[[ $status == 422 ]] || fail "a grid whose seam does not meet: $status $(cat "$out/open-grid.json")"
grep -q '"field":"surface.periodic_u"' "$out/open-grid.json" &&
  grep -q 'fails to meet by 1.5 ' "$out/open-grid.json" ||
  fail "the open grid's problem: $(cat "$out/open-grid.json")"

# A half cylinder has a seam no model may cross: 422 outside_sheet.
status=$(deform half '{"surface":{"kind":"cylinder","radius":1,"height":2,"angle_deg":180},
  "placement":{"center":[0,1]}}')
[[ $status == 422 ]] || fail "the half cylinder took a model off its sheet: $status"
grep -q '"code":"outside_sheet"' "$out/half.glb" || fail "half cylinder: $(cat "$out/half.glb")"

stop_served_server
echo "closed surfaces: all passed"
