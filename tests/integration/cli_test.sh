#!/usr/bin/env bash
# The `surfdeform` command-line client against the real server: every
# subcommand, every output format through a real decoder, the documented exit
# codes, retries (503 and unreachable) but never on 4xx, and batch runs that
# report failures per file and resume.
# Usage: cli_test.sh SERVER_BINARY CLI_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
samples="$here/../../client/web/samples"
server_bin=$1
cli=$2
out=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Starts a server with the given flags and sets the variable named $1 to its
# base URL (not in a subshell: the cleanup must know the pid).
source "$here/launch_server.sh"
start_server() {
  local var=$1
  shift
  launch_server "$server_bin" "$out/server-$RANDOM.log" "$@"
  pids+=("$SERVER_PID")
  disown  # killed by the cleanup, quietly
  printf -v "$var" 'http://127.0.0.1:%s' "$SERVER_PORT"
}

# Runs the client, expecting exit code $1; stdout and stderr go to $out/o, $out/e.
expect() {
  local want=$1
  shift
  local code=0
  "$cli" "$@" > "$out/o" 2> "$out/e" || code=$?
  [[ $code == "$want" ]] || fail "surfdeform $*: exit $code, expected $want; stderr: $(cat "$out/e")"
}

start_server base
export SURFDEFORM_SERVER=$base

# health, info.
expect 0 health
grep -q "live, ready" "$out/o" || fail "health output"
expect 0 info
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert "max_output_vertices" in j["limits"]' "$out/o" \
  || fail "info JSON"

# flatten: id, quality, the SVG of the flat sheet.
python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); s.pop("description"); json.dump({"surface": s, "sampling": {"nu": 16, "nv": 16}}, open(sys.argv[2], "w"))' \
  "$samples/figure10.json" "$out/figure10.json"
expect 0 flatten "$out/figure10.json" --svg "$out/flat.svg"
id=$(sed -n 's/^id \([0-9a-f]\{32\}\).*/\1/p' "$out/o")
[[ -n $id ]] || fail "flatten printed no id: $(cat "$out/o")"
grep -q "stress" "$out/o" || fail "flatten printed no quality"
grep -q '</svg>' "$out/flat.svg" || fail "flat.svg"
expect 0 flatten "$out/figure10.json" --json
grep -q '"cached": true' "$out/o" || fail "second flatten is not a cache hit"

# map: sheet points onto the surface, then back (the same sheet points), a
# polyline to a file; the server's 4xx is exit 2.
expect 0 map "$id" '{"points": [[5.0, 5.0], [3.0, 6.0]]}'
python3 -c 'import json,sys; print(json.dumps({"surface_points": [m["point"] for m in json.load(open(sys.argv[1]))["points"]]}))' \
  "$out/o" > "$out/back.json"
expect 0 map "$id" "$out/back.json" -o "$out/back-reply.json"
python3 - "$out/back-reply.json" << 'EOF' || fail "map back"
import json, sys
got = [m["sheet"] for m in json.load(open(sys.argv[1]))["surface_points"]]
for want, g in zip([[5.0, 5.0], [3.0, 6.0]], got):
    assert max(abs(a - b) for a, b in zip(want, g)) < 1e-9, (want, g)
EOF
expect 0 map "$id" '{"polylines": [[[2.0, 2.0], [8.0, 7.0]]], "tolerance": 0.01}' -o "$out/line.json"
grep -q '"polylines"' "$out/line.json" || fail "map polylines output"
expect 2 map "$id" '{"points": [[1, 2]], "tolerance": 1}'
grep -q "only polylines take it" "$out/e" || fail "map 4xx message: $(cat "$out/e")"

# deform: the output's extension picks the format; each checked by a real reader.
cyl='{"kind":"cylinder","radius":1,"height":2,"angle_deg":180}'
echo "$cyl" > "$out/cylinder.json"
expect 0 deform "$samples/bunny.ply" --surface "$out/cylinder.json" --scale fit -o "$out/bunny.drc"
draco_decoder -i "$out/bunny.drc" -o "$out/bunny_drc.obj" > /dev/null || fail "draco_decoder"
[[ $(grep -c '^f ' "$out/bunny_drc.obj") == 75408 ]] || fail "decoded .drc face count"
expect 0 deform "$samples/bunny.ply" --surface-id "$id" --scale fit -o "$out/bunny.glb"
[[ $(head -c 4 "$out/bunny.glb") == glTF ]] || fail ".glb magic"
# OBJ and PLY: Draco over the wire decoded here (sequential: vertex order kept),
# or --lossless straight from the server; with subdivision off both keep the
# bunny's 37,706 vertices in order.
expect 0 deform "$samples/bunny.ply" --surface-id "$id" --scale fit --subdivision off -o "$out/a.obj"
expect 0 deform "$samples/bunny.ply" --surface-id "$id" --scale fit --subdivision off --lossless -o "$out/b.obj"
[[ $(grep -c '^v ' "$out/a.obj") == 37706 && $(grep -c '^v ' "$out/b.obj") == 37706 ]] || fail "OBJ vertex counts"
python3 - "$out/a.obj" "$out/b.obj" << 'EOF' || fail "Draco-decoded OBJ differs from the lossless one beyond quantization"
import sys
def verts(p):
    return [tuple(map(float, l.split()[1:4])) for l in open(p) if l.startswith("v ")]
a, b = verts(sys.argv[1]), verts(sys.argv[2])
span = max(max(v[i] for v in b) - min(v[i] for v in b) for i in range(3))
worst = max(max(abs(x - y) for x, y in zip(p, q)) for p, q in zip(a, b))
assert worst < span * 2 ** -13, (worst, span)
EOF
expect 0 deform "$samples/bunny.ply" --surface-id "$id" --scale fit -o "$out/bunny.ply"
head -c 3 "$out/bunny.ply" | grep -q ply || fail ".ply header"

# A text as the model: shaped and meshed by the server; one group per glyph.
expect 0 deform --text "Ada" --font DejaVuSerif --size-mm 0.5 --depth-mm 0.05 --surface-id "$id" \
  --subdivision off -o "$out/ada.obj"
grep -q "^f " "$out/ada.obj" || fail "the text's OBJ has no faces"
expect 1 deform --text "Ada" "$samples/bunny.ply" --surface-id "$id" -o "$out/x.obj"
expect 2 deform --text "Ada" --font NoSuchFont --surface-id "$id" -o "$out/x.obj"
grep -q "text.font" "$out/e" || fail "an unknown font's refusal names text.font: $(cat "$out/e")"
# A batch of texts (a name per part): one output per non-empty line, named by
# its line and text; a second run skips them.
printf 'Ada Lovelace\n\nCharles Babbage\r\nΚαλημέρα\n' > "$out/names.txt"
expect 0 batch --texts "$out/names.txt" --surface-id "$id" --size-mm 0.4 --depth-mm 0.03 \
  --subdivision off --ext .obj -o "$out/names"
for f in 001-Ada-Lovelace 003-Charles-Babbage 004-Καλημέρα; do
  grep -q "^f " "$out/names/$f.obj" || fail "batch --texts wrote no $f.obj: $(ls "$out/names")"
done
[[ $(ls "$out/names" | wc -l) == 3 ]] || fail "batch --texts wrote $(ls "$out/names")"
expect 0 batch --texts "$out/names.txt" --surface-id "$id" --size-mm 0.4 --ext .obj -o "$out/names"
grep -q "3 skipped" "$out/e" || fail "a second batch --texts skips the written parts: $(cat "$out/e")"

# Models by id: every deform above sent the bunny by its id, uploading it
# once (on the first 404 unknown_model); `upload` prints that id (the first 32
# hex digits of the file's SHA-256), and `deform --model-id` gives the same
# bytes as sending the file.
uploads=$(curl -sS "$base/metrics" | sed -n 's|^surfdeform_http_requests_total{route="/v1/models",method="POST",status="201"} ||p')
[[ $uploads == 1 ]] || fail "the bunny was uploaded ${uploads:-0} times, expected once"
expect 0 upload "$samples/bunny.ply"
mid=$(cat "$out/o")
[[ $mid == "$(sha256sum "$samples/bunny.ply" | cut -c1-32)" ]] || fail "upload printed '$mid', not the bytes' id"
grep -q "ply, 37706 vertices, 75408 triangles, up +z (already on the server)" "$out/e" || fail "upload summary: $(cat "$out/e")"
expect 0 deform --model-id "$mid" --surface-id "$id" --scale fit -o "$out/by_id.glb"
cmp -s "$out/by_id.glb" "$out/bunny.glb" || fail "deform --model-id differs from deform with the file"
grep -q "^model $mid -> " "$out/o" || fail "deform --model-id summary: $(cat "$out/o")"
expect 2 deform --model-id 0123456789abcdef0123456789abcdef --surface-id "$id" -o "$out/x.glb"
grep -q "POST the mesh to /v1/models again" "$out/e" || fail "unknown model: $(cat "$out/e")"
expect 1 deform "$samples/bunny.ply" --model-id "$mid" --surface-id "$id" -o "$out/x.glb"
expect 1 deform --surface-id "$id" -o "$out/x.glb"
expect 4 upload "$out/missing.ply"

# The distortion map: in .ply (then lossless: Draco would drop it) with its
# summary printed; not in .obj or .drc (usage).
expect 0 deform "$samples/bunny.ply" --surface-id "$id" --scale fit --distortion -o "$out/dist.ply"
grep -q "distortion max" "$out/o" "$out/e" || fail "no distortion summary: $(cat "$out/o" "$out/e")"
grep -a -q "property float distortion_max" "$out/dist.ply" || fail "no distortion properties in the PLY"
expect 1 deform "$samples/bunny.ply" --surface-id "$id" --distortion -o "$out/dist.obj"
grep -q -- "--distortion: the distortion map is written in .glb and .ply output only" "$out/e" \
  || fail "distortion in .obj: $(cat "$out/e")"

# Exit codes: usage 1, refused 2 (not retried), local file 4, unreachable 3.
expect 1 deform "$samples/bunny.ply" --surface-id "$id" -o "$out/bunny.stl"
expect 1 deform "$samples/bunny.ply" -o "$out/x.drc"
expect 2 -v deform "$samples/bunny.ply" --surface-id "$id" --scale 50 -o "$out/big.drc"
grep -q "fall outside the flat sheet" "$out/e" || fail "the server's message: $(cat "$out/e")"
grep -q "retry" "$out/e" && fail "a 4xx was retried"
[[ ! -e $out/big.drc ]] || fail "an output was written for a refused request"
echo 'not json' > "$out/bad.json"
expect 4 flatten "$out/missing.json"
expect 4 flatten "$out/bad.json"
expect 4 deform "$samples/bunny.ply" --surface "$out/missing.json" -o "$out/x.drc"
expect 1 deform "$samples/bunny.ply" --surface-id "$id" --params "{not json" -o "$out/x.drc"
# Requests the API refuses are read by proto's parsers here and not sent:
# the server's message and exit code 2, even with no server to send them to.
expect 2 --server http://127.0.0.1:1 deform "$samples/bunny.ply" --surface-id "$id" \
  --params '{"placement":{"scale":-1}}' -o "$out/x.drc"
grep -q "placement.scale" "$out/e" || fail "a refused scale: $(cat "$out/e")"
expect 2 --server http://127.0.0.1:1 deform "$samples/bunny.ply" --surface "$out/cylinder.json" \
  --params '{"subdivision":{"tolerence":1}}' -o "$out/x.drc"
grep -q "subdivision.tolerence" "$out/e" || fail "an unknown field: $(cat "$out/e")"
expect 2 --server http://127.0.0.1:1 map "$id" '{"points": [[1, 2]], "tolerance": 1}'
grep -q "tolerance: only polylines take it" "$out/e" || fail "a refused map request: $(cat "$out/e")"
echo '{"kind":"cylindre","radius":2}' > "$out/misspelt.json"
expect 2 --server http://127.0.0.1:1 flatten "$out/misspelt.json"
grep -q "surface.kind" "$out/e" || fail "a refused surface file: $(cat "$out/e")"
expect 3 --server http://127.0.0.1:1 --retries 2 -v health
grep -q "retry 1" "$out/e" || fail "no retry report for a connection error"

# Global options work after the subcommand too (the environment points
# nowhere, so only --server can reach the server); misplaced and unknown
# options are named, with where they belong.
SURFDEFORM_SERVER=http://127.0.0.1:1 expect 0 deform "$samples/bunny.ply" --server "$base" \
  --retries 1 --timeout 60 -v --surface-id "$id" --scale fit -o "$out/after.drc"
[[ -s $out/after.drc ]] || fail "no output with --server after the subcommand"
SURFDEFORM_SERVER=http://127.0.0.1:1 expect 0 health --server="$base"
expect 1 --surface-id "$id" deform "$samples/bunny.ply" -o "$out/x.drc"
grep -q -- "--surface-id is an option of deform, batch and part: give it after the subcommand" "$out/e" \
  || fail "misplaced option message: $(cat "$out/e")"
expect 1 flatten "$out/figure10.json" --scale fit
grep -q -- "--scale is an option of deform, batch and animate, not of flatten" "$out/e" \
  || fail "option of another subcommand: $(cat "$out/e")"
expect 1 deform "$samples/bunny.ply" --surface-id "$id" -o "$out/x.drc" --bogus 3
grep -q -- "unknown option --bogus for deform" "$out/e" || fail "unknown option message: $(cat "$out/e")"

# animate: one GLB of morph targets, and each frame alone, with progress.
cat > "$out/wave.json" << 'JSON'
{"keyframes": [{"time": 0, "surface": {"kind": "wave", "length": 4, "width": 1, "amplitude": 0.2}}],
 "frames": 4, "fps": 8}
JSON
expect 0 animate "$samples/bunny.ply" --surface "$out/wave.json" --scale fit -o "$out/wave.glb" \
  --frames-dir "$out/frames" --frame-ext .ply
grep -q "wave.glb: 4 frames at 8 fps, 37706 vertices" "$out/o" || fail "animate summary: $(cat "$out/o")"
grep -q "animating 4 frames" "$out/e" || fail "animate progress: $(cat "$out/e")"
grep -q "frame 4/4 -> .*frame_0003.ply" "$out/e" || fail "frame progress: $(cat "$out/e")"
[[ $(head -c 4 "$out/wave.glb") == glTF ]] || fail "animate output is not a GLB"
ls "$out/frames"/frame_000{0,1,2,3}.ply > /dev/null || fail "frame files"
cmp -s "$out/frames/frame_0000.ply" "$out/frames/frame_0003.ply" && fail "frames 0 and 3 are the same"
expect 1 animate "$samples/bunny.ply" --surface "$out/wave.json" -o "$out/wave.drc"
grep -q "an animation is a GLB" "$out/e" || fail "animate .drc: $(cat "$out/e")"
expect 1 animate "$samples/bunny.ply" --surface "$out/cylinder.json" -o "$out/x.glb"
grep -q "an animation file holds" "$out/e" || fail "animate with a surface file: $(cat "$out/e")"
expect 1 animate "$samples/bunny.ply" --surface "$out/wave.json" -o "$out/x.glb" --compression zip
expect 2 --server http://127.0.0.1:1 animate "$samples/bunny.ply" --surface "$out/wave.json" \
  --params '{"output":{"distortion":true}}' -o "$out/x.glb"
grep -q "output.distortion" "$out/e" || fail "a refused animation: $(cat "$out/e")"
# Keyframes given as mesh files (a cloth's frames), named relative to the
# animation file: uploaded once, then animated like any keys.
mkdir -p "$out/cloth"
python3 - "$out/cloth" << 'PY'
import math, sys
for name, bend in (("flat.obj", 0.0), ("bent.obj", 0.8)):
    with open(sys.argv[1] + "/" + name, "w") as f:
        n = 9
        for j in range(n):
            for i in range(n):
                s = i / (n - 1)
                a = bend * (s - 0.5) * math.pi
                x, z = (math.sin(a) / bend, (1 - math.cos(a)) / bend) if bend else (s - 0.5, 0.0)
                f.write("v %.17g %.17g %.17g\n" % (x * 2, j / (n - 1), z * 2))
        for j in range(n - 1):
            for i in range(n - 1):
                a, b = 1 + i + n * j, 2 + i + n * j
                f.write("f %d %d %d\nf %d %d %d\n" % (a, b, b + n, a, b + n, a + n))
PY
cat > "$out/cloth/anim.json" << 'JSON'
{"animation": {"keyframes": [{"time": 0, "surface": "flat.obj"}, {"time": 1, "surface": "bent.obj"}],
               "frames": 3, "interpolation": "linear"},
 "sampling": {"nu": 16, "nv": 16}}
JSON
expect 0 animate "$samples/bunny.ply" --surface "$out/cloth/anim.json" --scale fit \
  --subdivision off -o "$out/cloth.glb"
grep -q "cloth.glb: 3 frames" "$out/o" || fail "animate along mesh keyframes: $(cat "$out/o") $(cat "$out/e")"
[[ $(head -c 4 "$out/cloth.glb") == glTF ]] || fail "mesh keyframes: not a GLB"
echo '{"keyframes": [{"time": 0, "surface": "missing.obj"}, {"time": 1, "surface": "bent.obj"}]}' \
  > "$out/cloth/missing.json"
expect 4 animate "$samples/bunny.ply" --surface "$out/cloth/missing.json" -o "$out/x.glb"
grep -q "missing.obj" "$out/e" || fail "a missing keyframe mesh: $(cat "$out/e")"
# The same keys given inline, named from here.
(cd "$out" && expect 0 animate "$samples/bunny.ply" --scale fit --subdivision off -o cloth-inline.glb \
  --surface '{"keyframes": [{"time": 0, "surface": "cloth/flat.obj"}, {"time": 1, "surface": "cloth/bent.obj"}], "frames": 2}')
grep -q "cloth-inline.glb: 2 frames" "$out/o" || fail "inline mesh keyframes: $(cat "$out/o") $(cat "$out/e")"

# 503: a server with one slot, held by a slow flattening; the client retries
# until the slot frees, then succeeds.
start_server busy --max-in-flight 1 --flatten-budget-ms 600000 --request-budget-ms 600000
curl -sS -o /dev/null -H 'Content-Type: application/json' \
  -d '{"surface":{"kind":"wave"},"sampling":{"nu":40,"nv":40},"flatten":{"method":"paper"}}' \
  "$busy/v1/surfaces" &
holder=$!
sleep 0.3
expect 0 --server "$busy" --retries 100 -v deform "$samples/bunny.ply" --surface "$out/cylinder.json" --scale fit -o "$out/retried.drc"
grep -q "busy (503)" "$out/e" || echo "note: the slow request finished before the client's request"
wait $holder || true
[[ -s $out/retried.drc ]] || fail "no output after retries"

# batch: a folder with two good meshes and a broken one.
mkdir -p "$out/in"
cp "$samples/bunny.ply" "$out/in/bunny.ply"
printf 'v -0.5 -0.25 -0.025\nv 0.5 -0.25 -0.025\nv 0.5 0.25 -0.025\nv -0.5 0.25 -0.025\nf 1 2 3 4\n' > "$out/in/plate.obj"
printf 'v 0 0 0\nf 1 2 99999\n' > "$out/in/broken.obj"
expect 5 batch "$out/in" -o "$out/batch" --ext .glb --surface "$out/cylinder.json" --scale fit -j 3
[[ -s $out/batch/bunny.glb && -s $out/batch/plate.glb && ! -e $out/batch/broken.glb ]] || fail "batch outputs"
grep -q "FAILED .*broken.obj: HTTP 422" "$out/o" || fail "batch failure line: $(cat "$out/o")"
grep -q "^ok .*plate.obj" "$out/o" || fail "plain progress lines when not a terminal"
grep -q "2 done, 0 skipped, 1 failed" "$out/e" || fail "batch summary: $(cat "$out/e")"
ls "$out/batch" | grep -q part && fail "a partial file was left behind"
# Resumed: done outputs are skipped, the broken one is tried again.
stamp=$(stat -c %Y "$out/batch/bunny.glb")
expect 5 batch "$out/in" -o "$out/batch" --ext .glb --surface "$out/cylinder.json" --scale fit
grep -q "0 done, 2 skipped, 1 failed" "$out/e" || fail "resumed batch: $(cat "$out/e")"
rm "$out/in/broken.obj"
expect 0 batch "$out/in" -o "$out/batch" --ext .glb --surface "$out/cylinder.json" --scale fit --force
grep -q "2 done, 0 skipped, 0 failed" "$out/e" || fail "forced batch: $(cat "$out/e")"
# A mesh file as the surface: uploaded, flattened as kind "mesh";
# a deformation along it by --surface; a closed mesh is the server's 422, exit 2.
expect 0 flatten "$samples/panel.obj"
grep -q "stress" "$out/o" || fail "flatten of a mesh file printed no quality: $(cat "$out/o")"
expect 0 deform "$samples/word.obj" --surface "$samples/panel.obj" --scale fit -o "$out/word-on-panel.glb"
[[ -s $out/word-on-panel.glb ]] || fail "no GLB along the panel mesh"
expect 0 batch "$out/in" -o "$out/batch-panel" --ext .glb --surface "$samples/panel.obj" --scale fit
grep -q "2 done, 0 skipped, 0 failed" "$out/e" || fail "batch along the panel mesh: $(cat "$out/e")"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n' > "$out/tetra.obj"
expect 2 flatten "$out/tetra.obj"
grep -q "the mesh is closed" "$out/e" || fail "a closed surface mesh: $(cat "$out/e")"

# A printable part: a ring from a whole cylinder, in mm, as 3MF and STL; a
# wall under the printer's minimum is a warning, with --strict the server's
# 422 (exit 2); --report writes the report.
echo '{"kind":"cylinder","radius":9,"height":6,"angle_deg":360}' > "$out/ring.json"
expect 0 part "$out/ring.json" --thickness-mm 1.8 -o "$out/ring.3mf"
[[ $(head -c 2 "$out/ring.3mf") == PK ]] || fail "the 3MF is not a package"
grep -q "closed and sound" "$out/o" || fail "part summary: $(cat "$out/o")"
expect 0 part "$out/ring.json" --thickness-mm 0.5 --min-wall-mm 0.8 -o "$out/thin.stl"
grep -q "thinner than the printer's minimum of 0.8 mm" "$out/e" || fail "thin wall warning: $(cat "$out/e")"
triangles=$(python3 -c 'import struct,sys; print(struct.unpack("<I", open(sys.argv[1],"rb").read()[80:84])[0])' "$out/thin.stl")
grep -q " $triangles triangles" "$out/o" || fail "the STL's $triangles triangles against the report: $(cat "$out/o")"
expect 2 part "$out/ring.json" --thickness-mm 0.5 --min-wall-mm 0.8 --strict -o "$out/strict.stl"
[[ ! -e $out/strict.stl ]] || fail "a refused part was written"
expect 0 part "$out/ring.json" --thickness-mm 1.8 --report -o "$out/ring-report.json"
python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); assert r["checks"]["closed"] and abs(r["volume_mm3"]-671.8)<3, r' "$out/ring-report.json" \
  || fail "part report"
expect 1 part "$out/ring.json" --thickness-mm 1.8 -o "$out/ring.xyz"

echo "cli: all checks passed"
