#!/usr/bin/env bash
# The API's curl examples (docs/api.md) against the real server: both body forms of
# POST /v1/deform, the surface routes, Draco output decoded by draco_decoder,
# GLB output through the Khronos glTF validator, and a clean SIGTERM exit.
# Usage: curl_examples.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
data="$here/../../client/web/samples"
source "$here/launch_server.sh"
serve_for_test "$1"

# Flatten the paper's Figure 10 surface once; deform by its id.
surface=$(python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); s.pop("description",None); print(json.dumps({"surface": s, "sampling": {"nu": 16, "nv": 16}}))' "$data/figure10.json")
curl -sS -f -o "$out/surface.json" -H 'Content-Type: application/json' -d "$surface" "$base/v1/surfaces"
id=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["id"])' "$out/surface.json")
[[ $id =~ ^[0-9a-f]{32}$ ]] || fail "surface id '$id'"
curl -sS -f -o "$out/flat.svg" "$base/v1/surfaces/$id/flat.svg"
grep -q '</svg>' "$out/flat.svg" || fail "flat.svg"

# Multipart: the bunny on the surface, Draco out, decoded by Draco's decoder.
curl -sS -f -o "$out/bunny.drc" -D "$out/headers.txt" \
  -F mesh=@"$data/bunny.ply" \
  -F "params={\"surface_id\":\"$id\",\"placement\":{\"scale\":\"fit\"}}" \
  "$base/v1/deform"
grep -qi '^x-surfdeform-stats: .*"vertices":37706' "$out/headers.txt" || fail "stats header"
draco_decoder -i "$out/bunny.drc" -o "$out/bunny.obj" > /dev/null
faces=$(grep -c '^f ' "$out/bunny.obj")
[[ $faces == 75408 ]] || fail "decoded $faces faces, expected 75408"

# Raw body, parameters in the query string, GLB (Draco-compressed) out,
# through the Khronos validator.
params=$(python3 -c 'import sys,urllib.parse; print(urllib.parse.quote(sys.argv[1]))' \
  '{"surface":{"kind":"cylinder","radius":1,"height":2,"angle_deg":180},"placement":{"scale":"fit"}}')
curl -sS -f -o "$out/bunny.glb" -H 'Accept: model/gltf-binary' \
  -H 'Content-Type: application/octet-stream' --data-binary @"$data/bunny.ply" \
  "$base/v1/deform?params=$params"
curl -sS -f -o "$out/bunny-plain.glb" -H 'Content-Type: application/octet-stream' \
  -H 'X-Surfdeform-Params: {"surface":{"kind":"cylinder","radius":1,"height":2,"angle_deg":180},"placement":{"scale":"fit"},"output":{"format":"glb_plain"}}' \
  --data-binary @"$data/bunny.ply" "$base/v1/deform"

# The distortion map (docs/api.md): GLB with _DISTORTION, the stats header's summary.
curl -sS -f -o "$out/bunny-distortion.glb" -D "$out/distortion-headers.txt" \
  --data-binary @"$data/bunny.ply" -H 'Content-Type: application/octet-stream' \
  -H 'X-Surfdeform-Params: {"surface":{"kind":"cylinder","radius":1,"height":2,"angle_deg":180},"placement":{"scale":"fit"},"output":{"format":"glb","distortion":true}}' \
  "$base/v1/deform"
python3 - "$out/bunny-distortion.glb" "$out/distortion-headers.txt" << 'PY' || fail "distortion map"
import json, struct, sys
glb = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", glb, 12)[0]
gltf = json.loads(glb[20:20 + n])
prim = gltf["meshes"][0]["primitives"][0]
assert "_DISTORTION" in prim["attributes"], prim["attributes"]
assert "_DISTORTION" in prim["extensions"]["KHR_draco_mesh_compression"]["attributes"]
line = [l for l in open(sys.argv[2]) if l.lower().startswith("x-surfdeform-stats:")][0]
d = json.loads(line.split(":", 1)[1])["distortion"]
assert 0 < d["mean"] <= d["p95"] <= d["max"] < 1, d
PY
status=$(curl -sS -o "$out/problem.json" -w '%{http_code}' --data-binary @"$data/bunny.ply" \
  -H 'Content-Type: application/octet-stream' \
  -H 'X-Surfdeform-Params: {"surface":{"kind":"cone"},"placement":{"scale":"fit"},"output":{"format":"obj","distortion":true}}' \
  "$base/v1/deform")
[[ $status == 422 ]] && grep -q '"field":"output.distortion"' "$out/problem.json" \
  || fail "distortion in OBJ gave $status: $(cat "$out/problem.json")"
node "$here/../gltf/validate.mjs" "$out/bunny.glb" "$out/bunny-plain.glb" "$out/bunny-distortion.glb"

# Rigid parts (docs/api.md): a word of three box glyphs on a cylinder, each glyph
# keeps its edge lengths; the stats report the parts and their corners' lift.
python3 - "$out/word.obj" << 'PY'
import sys
with open(sys.argv[1], "w") as f:
    for g in range(3):
        x0 = 0.4 * (g - 1) - 0.15
        for dx in (0, 0.3):
            for dy in (-0.2, 0.2):
                for dz in (-0.025, 0.025):
                    f.write("v %g %g %g\n" % (x0 + dx, dy, dz))
        b = 8 * g + 1  # corners: index = 4*ix + 2*iy + iz
        for q in ((0, 2, 6, 4), (1, 5, 7, 3), (0, 4, 5, 1), (2, 3, 7, 6), (0, 1, 3, 2), (4, 6, 7, 5)):
            f.write("f %s\n" % " ".join(str(b + i) for i in q))
PY
curl -sS -f -o "$out/word-on-cylinder.obj" -D "$out/word-headers.txt" --data-binary @"$out/word.obj" \
  -H 'Content-Type: application/octet-stream' \
  -H 'X-Surfdeform-Params: {"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"placement":{"scale":1,"rigid":"components"},"output":{"format":"obj"}}' \
  "$base/v1/deform"
python3 - "$out/word.obj" "$out/word-on-cylinder.obj" "$out/word-headers.txt" << 'PY' || fail "rigid parts"
import json, math, sys
def verts(p):
    return [tuple(map(float, l.split()[1:4])) for l in open(p) if l.startswith("v ")]
a, b = verts(sys.argv[1]), verts(sys.argv[2])
assert len(a) == len(b) == 24, (len(a), len(b))
for g in range(3):
    for i in range(8):
        for j in range(i + 1, 8):
            d0, d1 = math.dist(a[8 * g + i], a[8 * g + j]), math.dist(b[8 * g + i], b[8 * g + j])
            assert abs(d0 - d1) < 1e-6 * d0, (g, i, j, d0, d1)  # OBJ's 9 digits
line = [l for l in open(sys.argv[3]) if l.lower().startswith("x-surfdeform-stats:")][0]
rigid = json.loads(line.split(":", 1)[1])["rigid"]
assert rigid["mode"] == "components" and rigid["parts"] == 3 and len(rigid["each"]) == 3, rigid
assert abs(rigid["max_lift"] - (2 * math.cos(0.075) + 0.15 * math.sin(0.075) - 2)) < 1e-9, rigid
PY

# A textured glTF (docs/api.md) comes back textured: its image byte for byte, and
# the Khronos validator accepts the GLB. Being glTF, it stands on its +Y
# (placement.up "auto", the default).
box=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
curl -sS -f -o "$out/box-on-cylinder.glb" -D "$out/box-headers.txt" --data-binary @"$box" -H 'Content-Type: application/octet-stream' \
  -H 'X-Surfdeform-Params: {"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"placement":{"scale":"fit"},"output":{"format":"glb"}}' \
  "$base/v1/deform"
python3 - "$out/box-on-cylinder.glb" /usr/share/assimp/models/glTF2/BoxTextured-glTF/CesiumLogoFlat.png << 'PY' || fail "textured GLB"
import json, struct, sys
glb = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", glb, 12)[0]
gltf = json.loads(glb[20:20 + n])
(image,) = gltf["images"]
view = gltf["bufferViews"][image["bufferView"]]
start = 20 + n + 8 + view.get("byteOffset", 0)
assert glb[start:start + view["byteLength"]] == open(sys.argv[2], "rb").read(), "image bytes differ"
assert gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] == 0
PY
node "$here/../gltf/validate.mjs" "$out/box-on-cylinder.glb"
grep -qi '^x-surfdeform-stats: .*"up":"+y","up_reason":"gltf"' "$out/box-headers.txt" \
  || fail "a glTF model with up auto: $(grep -i stats "$out/box-headers.txt")"

# Marks (docs/api.md): sheet points onto the surface, and those surface points
# back onto the sheet: the same sheet points to 1e-9; a polyline resampled.
cyl=$(curl -sS -f -H 'Content-Type: application/json' \
  -d '{"surface":{"kind":"cylinder","radius":1,"height":2,"angle_deg":180}}' "$base/v1/surfaces" \
  | python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')
curl -sS -f -o "$out/marks.json" -H 'Content-Type: application/json' \
  -d '{"points":[[1.0,1.0],[2.5,0.4]]}' "$base/v1/surfaces/$cyl/map"
back=$(python3 -c 'import json,sys; print(json.dumps({"surface_points": [m["point"] for m in json.load(open(sys.argv[1]))["points"]]}))' "$out/marks.json")
curl -sS -f -o "$out/back.json" -H 'Content-Type: application/json' -d "$back" "$base/v1/surfaces/$cyl/map"
curl -sS -f -o "$out/line.json" -H 'Content-Type: application/json' \
  -d '{"polylines":[[[0.2,1.0],[3.0,1.0]]],"tolerance":0.001}' "$base/v1/surfaces/$cyl/map"
python3 - "$out/marks.json" "$out/back.json" "$out/line.json" << 'PY' || fail "map round trip"
import json, math, sys
there = json.load(open(sys.argv[1]))["points"]
back = json.load(open(sys.argv[2]))["surface_points"]
for want, m in zip([[1.0, 1.0], [2.5, 0.4]], back):
    assert max(abs(a - b) for a, b in zip(want, m["sheet"])) < 1e-9, (want, m)
    assert m["distance"] < 1e-9 and m["on_sheet"], m
assert abs(there[0]["point"][0] - math.cos(1.0)) < 1e-9, there[0]
line = json.load(open(sys.argv[3]))["polylines"][0]
assert len(line) > 10 and line[0]["sheet"] == [0.2, 1.0] and line[-1]["sheet"] == [3.0, 1.0], len(line)
PY

# An error is problem+json with the right status.
status=$(curl -sS -o "$out/problem.json" -w '%{http_code}' -F mesh=@"$data/bunny.ply" \
  -F 'params={"surface":{"kind":"cylinder","radius":0}}' "$base/v1/deform")
[[ $status == 422 ]] || fail "zero radius gave $status"
grep -q '"field":"surface.radius"' "$out/problem.json" || fail "problem field"

# The API's animation example: the bunny swimming along the wave, one GLB.
curl -sS -f -o "$out/bunny-swims.glb" -F mesh=@"$data/bunny.ply" \
     -F 'params={"animation":{"keyframes":[{"time":0,"surface":{"kind":"wave","length":4,"width":1.5,"amplitude":0.25,"wavelength":2}}],"frames":60,"fps":30},"placement":{"scale":"fit"}}' \
     "$base/v1/animate"
python3 - "$out/bunny-swims.glb" << 'PY' || fail "the animation example"
import json, struct, sys
glb = open(sys.argv[1], "rb").read()
doc = json.loads(glb[20:20 + struct.unpack_from("<I", glb, 12)[0]])
assert len(doc["meshes"][0]["primitives"][0]["targets"]) == 60
assert "EXT_meshopt_compression" in doc["extensionsRequired"]
assert doc["animations"][0]["channels"][0]["target"]["path"] == "weights"
PY

# The contract: the served openapi.yaml is the committed one, every path in it
# is routed (never 404), and its request examples are accepted.
curl -sS -f -o "$out/openapi.yaml" "$base/openapi.yaml"
cmp -s "$out/openapi.yaml" "$here/../../proto/openapi.yaml" || fail "served openapi.yaml differs"
python3 - "$out/openapi.yaml" "$base" "$data/bunny.ply" "$cyl" <<'PY'
import json, sys, urllib.request, urllib.error, yaml
spec = yaml.safe_load(open(sys.argv[1]))
base = sys.argv[2]
def call(method, path, body=None, headers={}):
    req = urllib.request.Request(base + path, data=body, method=method, headers=headers)
    try:
        with urllib.request.urlopen(req) as r:
            return r.status
    except urllib.error.HTTPError as e:
        return e.code
for path, item in spec["paths"].items():
    concrete = path.replace("{id}", "0123456789abcdef0123456789abcdef")
    for method in item:
        status = call(method.upper(), concrete, b"{}" if method == "post" else None,
                      {"Content-Type": "application/json"})
        # An unknown id is 404 with problem+json; the route itself must exist.
        assert status != 405, (method, path, status)
        assert status != 404 or "{id}" in path, (method, path, status)
examples = spec["paths"]["/v1/surfaces"]["post"]["requestBody"]["content"]["application/json"]["examples"]
for name, ex in examples.items():
    status = call("POST", "/v1/surfaces", json.dumps(ex["value"]).encode(), {"Content-Type": "application/json"})
    assert status in (200, 201), (name, status)
marks = spec["paths"]["/v1/surfaces/{id}/map"]["post"]["requestBody"]["content"]["application/json"]["examples"]
for name, ex in marks.items():
    status = call("POST", "/v1/surfaces/%s/map" % sys.argv[4], json.dumps(ex["value"]).encode(),
                  {"Content-Type": "application/json"})
    assert status == 200, ("map example", name, status)
params = spec["components"]["schemas"]["DeformParams"]["example"]
status = call("POST", "/v1/deform", open(sys.argv[3], "rb").read(),
              {"Content-Type": "application/octet-stream", "X-Surfdeform-Params": json.dumps(params)})
assert status == 200, ("DeformParams example", status)
animate = spec["components"]["schemas"]["AnimateParams"]["example"]
status = call("POST", "/v1/animate", open(sys.argv[3], "rb").read(),
              {"Content-Type": "application/octet-stream", "X-Surfdeform-Params": json.dumps(animate)})
assert status == 200, ("AnimateParams example", status)
part = spec["components"]["schemas"]["PartRequest"]["example"]
status = call("POST", "/v1/parts", json.dumps(part).encode(), {"Content-Type": "application/json"})
assert status == 200, ("PartRequest example", status)
# Every named choice in the contract is the server's table, name for name and
# in order (the tables are published at /v1/info).
with urllib.request.urlopen(base + "/v1/info") as r:
    published = json.load(r)["enums"]
schemas = spec["components"]["schemas"]
contract = {
    "surface.kind": schemas["Surface"]["properties"]["kind"]["enum"],
    "flatten.method": schemas["Flatten"]["properties"]["method"]["enum"],
    "placement.up": schemas["Placement"]["properties"]["up"]["enum"],
    "placement.rigid": schemas["Placement"]["properties"]["rigid"]["enum"],
    "placement.anchor": schemas["Placement"]["properties"]["anchor"]["oneOf"][0]["enum"],
    "placement.outside": schemas["Placement"]["properties"]["outside"]["enum"],
    "output.format": schemas["Output"]["properties"]["format"]["enum"],
    "subdivision.mode": schemas["Subdivision"]["properties"]["mode"]["enum"],
    "animation.interpolation": schemas["Animation"]["properties"]["interpolation"]["enum"],
    "output.compression": schemas["Output"]["properties"]["compression"]["enum"],
    "problem.code": schemas["Problem"]["properties"]["code"]["enum"],
    "body.side": schemas["PartBody"]["properties"]["side"]["enum"],
}
assert sorted(contract) == sorted(published), (sorted(contract), sorted(published))
for field, names in contract.items():
    served = [e["name"] for e in published[field]]
    assert names == served, (field, "openapi.yaml", names, "server", served)
print("openapi: %d paths routed, %d examples accepted, %d enums match the server's tables"
      % (len(spec["paths"]), len(examples) + len(marks) + 3, len(contract)))
PY

stop_served_server
echo "curl examples: all passed"
