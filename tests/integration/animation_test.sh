#!/usr/bin/env bash
# POST /v1/animate against the real server: the bunny on a Bezier keyframe
# pair (Figure 10 bending), as a meshopt GLB and its uncompressed twin; the
# twin through the Khronos validator; the twin's morph targets against single
# frames from POST /v1/deform, and the meshopt file decoded by three.js's
# MeshoptDecoder (tests/gltf/check_animation.mjs); a textured GLB with normals;
# the errors a user meets (keys that do not match, too many frames, ...).
# Usage: animation_test.sh SERVER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
data="$here/../../client/web/samples"
gltf="$here/../gltf"
source "$here/launch_server.sh"
serve_for_test "$1"

# The animation: Figure 10's heights x0.6 at time 0, x1 at time 1; 5 frames.
python3 - "$data/figure10.json" "$out" << 'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s.pop("description", None)
def scaled(k):
    t = json.loads(json.dumps(s))
    t["control_points"] = [[x, y, z * k] for x, y, z in t["control_points"]]
    return t
anim = {"keyframes": [{"time": 0, "surface": scaled(0.6)}, {"time": 1, "surface": s}],
        "interpolation": "cubic", "frames": 5, "fps": 10}
common = {"animation": anim, "sampling": {"nu": 16, "nv": 16}, "placement": {"scale": "fit"}}
json.dump(dict(common, output={"compression": "meshopt"}), open(sys.argv[2] + "/animate.json", "w"))
json.dump(dict(common, output={"compression": "none"}), open(sys.argv[2] + "/animate-plain.json", "w"))
for k in (0, 2, 4):
    json.dump(dict(common, frame=k, output={"format": "glb_plain"}),
              open(sys.argv[2] + "/frame%d.json" % k, "w"))
# Errors.
bad = json.loads(json.dumps(common))
bad["animation"]["keyframes"][1]["surface"]["degree_u"] = 2
json.dump(bad, open(sys.argv[2] + "/bad-degree.json", "w"))
many = json.loads(json.dumps(common))
many["animation"]["frames"] = 100000
json.dump(many, open(sys.argv[2] + "/too-many.json", "w"))
single = json.loads(json.dumps(common))
single["animation"]["keyframes"] = single["animation"]["keyframes"][:1]
json.dump(single, open(sys.argv[2] + "/single.json", "w"))
json.dump(dict(common, frame=5), open(sys.argv[2] + "/frame-past.json", "w"))
heavy = json.loads(json.dumps(common))
heavy["animation"]["frames"] = 300  # 300 x 37,706 bunny vertices: past 8 M
json.dump(heavy, open(sys.argv[2] + "/too-heavy.json", "w"))
json.dump(dict(common, output={"format": "drc"}), open(sys.argv[2] + "/animate-drc.json", "w"))
PY

curl -sS -f -o "$out/anim.glb" -D "$out/anim-headers.txt" -F mesh=@"$data/bunny.ply" \
  -F "params=<$out/animate.json" "$base/v1/animate"
grep -qi '^content-type: model/gltf-binary' "$out/anim-headers.txt" || fail "content type"
grep -qi '^x-surfdeform-stats: .*"frames":5' "$out/anim-headers.txt" || fail "stats: frames"
# Five frames have two anchors (0 and 4): too few to interpolate paths through.
grep -qi '^x-surfdeform-stats: .*"paths_reused":0,' "$out/anim-headers.txt" ||
  fail "stats: paths_reused"
if grep -qi '"paths_reused":[1-9]' "$out/anim-headers.txt"; then fail "paths reused with 2 anchors"; fi
grep -qi '^x-surfdeform-stats: .*"cached":false' "$out/anim-headers.txt" || fail "first request cached?"
# The twin: the same sheets, from the cache.
curl -sS -f -o "$out/anim-plain.glb" -D "$out/plain-headers.txt" -F mesh=@"$data/bunny.ply" \
  -F "params=<$out/animate-plain.json" "$base/v1/animate"
grep -qi '^x-surfdeform-stats: .*"cached":true' "$out/plain-headers.txt" || fail "second request not cached"
# Not flattened again: its frames' flattening records are the first
# request's, timings and all (a new flattening would time itself anew).
python3 - "$out/anim-headers.txt" "$out/plain-headers.txt" << 'PY' || fail "the cached animation was flattened again"
import json, sys
def each(name):
    for line in open(name, encoding="utf-8", errors="replace"):
        if line.lower().startswith("x-surfdeform-stats:"):
            return json.loads(line.split(":", 1)[1])["flatten"]["each"]
first, twin = each(sys.argv[1]), each(sys.argv[2])
assert len(first) == 5 and twin == first, (first, twin)
PY
for k in 0 2 4; do
  curl -sS -f -o "$out/frame$k.glb" -F mesh=@"$data/bunny.ply" -F "params=<$out/frame$k.json" \
    "$base/v1/deform"
done
node "$gltf/validate.mjs" "$out/anim-plain.glb"
node "$gltf/check_animation.mjs" "$out/anim.glb" "$out/anim-plain.glb" 10 \
  0 "$out/frame0.glb" 2 "$out/frame2.glb" 4 "$out/frame4.glb"
# The check can fail: frame 4 given as frame 0.
if node "$gltf/check_animation.mjs" "$out/anim.glb" "$out/anim-plain.glb" 10 0 "$out/frame4.glb" \
  > /dev/null 2>&1; then
  fail "check_animation accepted frame 4 as frame 0"
fi
echo "negative control: a wrong frame is rejected"
size=$(stat -c %s "$out/anim.glb")
plain_size=$(stat -c %s "$out/anim-plain.glb")
((size * 4 < plain_size * 3)) || fail "meshopt output $size bytes, uncompressed $plain_size"

# The placement follows the surface: on a pair whose sheet
# shrinks, moves and turns, "center" is resolved on every frame's sheet, so
# the last frame is the static deformation on the last key; and "fit" fits
# every frame, the tightest deciding, where fitting the first alone leaves
# the last sheet.
python3 - "$data/figure10.json" "$out" << 'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s.pop("description", None)
def key(height, shrink):
    t = json.loads(json.dumps(s))
    t["control_points"] = [[x * shrink, y * shrink, z * height] for x, y, z in t["control_points"]]
    return t
first, last = key(0.3, 1.0), key(1.2, 0.8)
anim = {"keyframes": [{"time": 0, "surface": first}, {"time": 1, "surface": last}], "frames": 5}
plain = {"format": "glb_plain"}
sampling = {"nu": 16, "nv": 16}
placement = {"scale": 0.7, "center": "center", "rotation_deg": 20}
json.dump({"animation": anim, "sampling": sampling, "placement": placement, "frame": 4,
           "output": plain}, open(sys.argv[2] + "/follow-frame4.json", "w"))
json.dump({"surface": last, "sampling": sampling, "placement": placement, "output": plain},
          open(sys.argv[2] + "/follow-static.json", "w"))
fit = {"keyframes": [{"time": 0, "surface": key(0.2, 1.0)}, {"time": 1, "surface": key(1.0, 0.75)}],
       "frames": 12}
json.dump({"animation": fit, "sampling": sampling, "placement": {"scale": "fit"},
           "output": {"compression": "none"}}, open(sys.argv[2] + "/fit-shrinking.json", "w"))
PY
for name in follow-frame4 follow-static; do
  curl -sS -f -o "$out/$name.glb" -F mesh=@"$data/bunny.ply" -F "params=<$out/$name.json" \
    "$base/v1/deform"
done
python3 "$gltf/glb_positions.py" compare "$out/follow-frame4.glb" "$out/follow-static.glb" 1e-4 ||
  fail "the last frame is not the static deformation on the last key"
curl -sS -f -o "$out/fit.glb" -D "$out/fit-headers.txt" -F mesh=@"$data/bunny.ply" \
  -F "params=<$out/fit-shrinking.json" "$base/v1/animate"
grep -qi '^x-surfdeform-stats: .*"fit_frame":11' "$out/fit-headers.txt" ||
  fail "fit: the last, smallest sheet should decide: $(grep -i x-surfdeform-stats "$out/fit-headers.txt")"
node "$gltf/validate.mjs" "$out/fit.glb"

# A textured GLB with normals: normal targets, its texture carried.
box=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
curl -sS -f -o "$out/box.glb" -H 'Content-Type: application/octet-stream' \
  -H "X-Surfdeform-Params: $(python3 -c 'import json,sys; p=json.load(open(sys.argv[1])); p["output"]={"compression":"none"}; print(json.dumps(p))' "$out/animate.json")" \
  --data-binary @"$box" "$base/v1/animate"
node "$gltf/validate.mjs" "$out/box.glb"
python3 - "$out/box.glb" << 'PY' || fail "textured animation"
import json, struct, sys
glb = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", glb, 12)[0]
doc = json.loads(glb[20:20 + n])
prim = doc["meshes"][0]["primitives"][0]
assert "NORMAL" in prim["targets"][1], prim["targets"][1]
assert doc.get("images") and doc.get("textures"), "the texture did not travel"
assert "TEXCOORD_0" in prim["attributes"]
PY

# What a user gets wrong.
expect() {  # STATUS FIELD PARAMS_FILE [PATH [ACCEPT]]
  local status
  status=$(curl -sS -o "$out/problem.json" -w '%{http_code}' -F mesh=@"$data/bunny.ply" \
    -H "Accept: ${5:-*/*}" -F "params=<$3" "$base${4:-/v1/animate}")
  [[ $status == "$1" ]] || fail "$3 gave $status: $(cat "$out/problem.json")"
  grep -qF "\"field\":\"$2\"" "$out/problem.json" || fail "$3: field: $(cat "$out/problem.json")"
}
expect 422 animation.keyframes[1].surface.degree_u "$out/bad-degree.json"
expect 413 animation.frames "$out/too-many.json"
grep -q '"limit":600' "$out/problem.json" || fail "the frame limit is not stated"
expect 413 animation.frames "$out/too-heavy.json"
grep -q '"limit":8000000' "$out/problem.json" || fail "the frame-vertex limit is not stated"
expect 422 animation.keyframes "$out/single.json"
expect 422 frame "$out/frame-past.json" /v1/deform
expect 422 output.format "$out/animate-drc.json"
# An animation is only ever a GLB: an Accept header that refuses it is 406.
expect 406 Accept "$out/animate.json" /v1/animate application/octet-stream
expect 406 Accept "$out/animate.json" /v1/animate "model/gltf-binary;q=0, application/x-ply"

stop_served_server
echo "animation: all passed"
