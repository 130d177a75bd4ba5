#!/usr/bin/env python3
"""Fixed requests against a running server, one line each: the route, the
status, the ETag, the SHA-256 of the body and the X-Surfdeform-Stats header
without its timings. Two builds that answer alike print the same lines
(bench/behaviour_diff.sh compares them).

Usage: behaviour_snapshot.py PORT SAMPLES_DIR
"""
import hashlib
import json
import sys
import urllib.error
import urllib.parse
import urllib.request

port, samples = sys.argv[1], sys.argv[2]
base = f"http://127.0.0.1:{port}"


def read(name):
    with open(f"{samples}/{name}", "rb") as f:
        return f.read()


def without_timings(stats):
    """The stats header with every wall-time field dropped ("ms", "*_ms")."""
    if isinstance(stats, dict):
        return {k: without_timings(v) for k, v in stats.items()
                if k != "ms" and not k.endswith("_ms") and k != "timing_ms"}
    if isinstance(stats, list):
        return [without_timings(v) for v in stats]
    return stats


def call(name, method, path, body=None, headers=None, keep_body=False):
    req = urllib.request.Request(base + path, data=body, method=method, headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=120) as r:
            status, h, data = r.status, r.headers, r.read()
    except urllib.error.HTTPError as e:
        status, h, data = e.code, e.headers, e.read()
    if h.get("Content-Type", "").startswith("application/json") or "problem" in h.get(
            "Content-Type", ""):
        doc = json.loads(data)
        doc = without_timings(doc)
        doc.pop("request_id", None)  # differs on every request
        digest_of = json.dumps(doc, sort_keys=True).encode()
    else:
        digest_of = data
    # JSON bodies are compared (and sized) without their timings, whose
    # digits vary from run to run.
    stats = h.get("X-Surfdeform-Stats")
    stats = json.dumps(without_timings(json.loads(stats)), sort_keys=True) if stats else "-"
    etag = h.get("ETag", "-") if not h.get("Content-Type", "").startswith("application/json") \
        else "(json)"
    print(f"{name}\t{status}\t{h.get('Content-Type', '-')}\tetag={etag}\t"
          f"sha256={hashlib.sha256(digest_of).hexdigest()[:24]}\tbytes={len(digest_of)}\tstats={stats}")
    return data if keep_body else None


fig10 = json.loads(read("figure10.json"))
fig10.pop("description", None)
surface = {"surface": fig10, "sampling": {"nu": 16, "nv": 16}}
cylinder = {"kind": "cylinder", "radius": 1, "height": 2, "angle_deg": 180}
bunny, word = read("bunny.ply"), read("word.obj")
raw = {"Content-Type": "application/octet-stream"}

call("info", "GET", "/v1/info")
created = call("create surface", "POST", "/v1/surfaces", json.dumps(surface).encode(),
               {"Content-Type": "application/json"}, keep_body=True)
sid = json.loads(created)["id"]
call("create surface again", "POST", "/v1/surfaces", json.dumps(surface).encode(),
     {"Content-Type": "application/json"})
call("get surface", "GET", f"/v1/surfaces/{sid}")
call("flat.svg", "GET", f"/v1/surfaces/{sid}/flat.svg")
call("map points", "POST", f"/v1/surfaces/{sid}/map",
     json.dumps({"points": [[0.1, 0.2], [0.5, -0.3], [9, 9]]}).encode(),
     {"Content-Type": "application/json"})
call("map polyline", "POST", f"/v1/surfaces/{sid}/map",
     json.dumps({"polylines": [[[0, 0], [0.5, 0.5], [1, 0.2]]]}).encode(),
     {"Content-Type": "application/json"})
for fmt in ["drc", "glb", "glb_plain", "ply", "obj"]:
    params = {"surface_id": sid, "placement": {"scale": "fit"}, "output": {"format": fmt}}
    call(f"deform bunny {fmt}", "POST", "/v1/deform", bunny,
         {**raw, "X-Surfdeform-Params": json.dumps(params)})
call("deform bunny again (memo)", "POST", "/v1/deform", bunny,
     {**raw, "X-Surfdeform-Params": json.dumps({"surface_id": sid,
                                                 "placement": {"scale": "fit"}})})
call("deform bunny by query, Accept glb", "POST",
     "/v1/deform?params=" + urllib.parse.quote(json.dumps(
         {"surface": cylinder, "placement": {"scale": "fit"}})),
     bunny, {**raw, "Accept": "model/gltf-binary"})
call("deform bunny distortion", "POST", "/v1/deform", bunny,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface": cylinder, "placement": {"scale": "fit"},
          "output": {"format": "glb", "distortion": True}})})
call("deform word adaptive", "POST", "/v1/deform", word,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface": {"kind": "cylinder", "radius": 2, "height": 3, "angle_deg": 180},
          "placement": {"scale": 1}, "subdivision": {"mode": "adaptive"},
          "output": {"format": "ply"}})})
call("deform word uniform twice", "POST", "/v1/deform", word,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface_id": sid, "placement": {"scale": "fit"},
          "subdivision": {"mode": "uniform"}, "output": {"format": "obj"}})})
call("deform word rigid", "POST", "/v1/deform", word,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface": {"kind": "cylinder", "radius": 2, "height": 3, "angle_deg": 180},
          "placement": {"scale": 1, "rigid": "components"}, "output": {"format": "obj"}})})
swim = json.loads(read("swim.json"))
swim.pop("description", None)
call("animate word", "POST", "/v1/animate", word,
     {**raw, "X-Surfdeform-Params": json.dumps({**swim, "placement": {"scale": "fit"}})})
call("animate word plain", "POST", "/v1/animate", word,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {**swim, "placement": {"scale": "fit"}, "output": {"compression": "none"}})})
call("deform word frame 7", "POST", "/v1/deform", word,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {**swim, "frame": 7, "placement": {"scale": "fit"}, "output": {"format": "glb"}})})
cone = json.loads(read("cone.json"))
cone.pop("description", None)
call("deform bunny on cone (multipart)", "POST", "/v1/deform",
     b"--XyZ\r\nContent-Disposition: form-data; name=\"mesh\"; filename=\"b.ply\"\r\n\r\n"
     + bunny + b"\r\n--XyZ\r\nContent-Disposition: form-data; name=\"params\"\r\n\r\n"
     + json.dumps({"surface": cone, "placement": {"scale": "fit"}, "output": {"format": "ply"}}).encode()
     + b"\r\n--XyZ--\r\n",
     {"Content-Type": "multipart/form-data; boundary=XyZ"})
# Text: a deformation of words (twice: the second is the kept answer), and
# the words' mesh alone.
jsn = {"Content-Type": "application/json"}
text = {"string": "Ada", "size_mm": 0.3, "depth_mm": 0.05}
for n in ("text on cylinder", "text on cylinder again (kept)"):
    call(n, "POST", "/v1/deform", json.dumps(
        {"surface": cylinder, "text": text, "placement": {"rigid": "components"},
         "output": {"format": "obj"}}).encode(), jsn)
call("text alone", "POST", "/v1/text", json.dumps({"text": text, "output": {"format": "ply"}}).encode(), jsn)
# An edit and its deformation in one request, warm-started from Figure 10.
edited = json.loads(json.dumps(fig10))
edited["control_points"][5][2] += 0.1
call("deform word on an edit (warm start)", "POST", "/v1/deform", word,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface": edited, "sampling": {"nu": 16, "nv": 16}, "warm_start": sid,
          "placement": {"scale": 1, "center": [5.0, 5.0]}, "output": {"format": "obj"}})})
# Errors: a problem each, by class.
call("error: unknown surface", "GET", "/v1/surfaces/" + "0" * 32)
call("error: bad json", "POST", "/v1/surfaces", b"{", {"Content-Type": "application/json"})
call("error: grid too big", "POST", "/v1/surfaces",
     json.dumps({"surface": cylinder, "sampling": {"nu": 999, "nv": 4}}).encode(),
     {"Content-Type": "application/json"})
call("error: outside the sheet", "POST", "/v1/deform", bunny,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface_id": sid, "placement": {"scale": 5, "outside": "error"}})})
call("outside the sheet, clamped", "POST", "/v1/deform", bunny,
     {**raw, "X-Surfdeform-Params": json.dumps(
         {"surface_id": sid, "placement": {"scale": 5, "outside": "clamp"},
          "output": {"format": "ply"}})})
call("error: no mesh", "POST", "/v1/deform", b"",
     {**raw, "X-Surfdeform-Params": json.dumps({"surface_id": sid})})
call("error: animate accepts glb only", "POST", "/v1/animate", word,
     {**raw, "Accept": "text/plain", "X-Surfdeform-Params": json.dumps(swim)})
call("error: method", "DELETE", "/v1/deform")
call("healthz", "GET", "/healthz")
call("openapi", "GET", "/openapi.yaml")
