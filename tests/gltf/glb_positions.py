"""Positions of a plain GLB's first primitive, and a comparison of two.

  glb_positions.py compare A.glb B.glb TOLERANCE [--half-turn]
  glb_positions.py radius A.glb RADIUS TOLERANCE
  glb_positions.py nearest A.glb B.glb TOLERANCE

compares the first min(count) positions (the input's vertices come first, in
order, in every answer): their largest coordinate difference must stay
within TOLERANCE. With --half-turn, B is turned half a turn about +Z first,
(x, y, z) -> (-x, -y, z). Prints the difference; exits 1 past the tolerance.

radius checks that every position lies RADIUS from the origin (on a sphere
about it), within TOLERANCE.

nearest compares the two as point sets: every position of A must have one of
B within TOLERANCE (for answers whose frames may differ by a symmetry of the
model).
"""
import json
import math
import struct
import sys


def positions(path):
    glb = open(path, "rb").read()
    n = struct.unpack_from("<I", glb, 12)[0]
    doc = json.loads(glb[20:20 + n])
    binary = glb[20 + n + 8:]
    acc = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    flat = struct.unpack_from("<%df" % (3 * acc["count"]), binary, start)
    return [flat[k:k + 3] for k in range(0, len(flat), 3)]


def main(argv):
    if len(argv) == 5 and argv[1] == "radius":
        radius, tolerance = float(argv[3]), float(argv[4])
        worst = max(abs(math.sqrt(x * x + y * y + z * z) - radius) for x, y, z in positions(argv[2]))
        print("off the sphere of radius %g by at most %.3g" % (radius, worst))
        return 0 if worst <= tolerance else 1
    if len(argv) == 5 and argv[1] == "nearest":
        a, b = positions(argv[2]), positions(argv[3])
        worst = max(min(math.dist(p, q) for q in b) for p in a)
        print("%d positions each within %.3g of one of %d" % (len(a), worst, len(b)))
        return 0 if worst <= float(argv[4]) else 1
    if len(argv) < 5 or argv[1] != "compare":
        print(__doc__, file=sys.stderr)
        return 2
    a, b = positions(argv[2]), positions(argv[3])
    tolerance = float(argv[4])
    if "--half-turn" in argv[5:]:
        b = [(-x, -y, z) for x, y, z in b]
    n = min(len(a), len(b))
    worst = max(abs(p - q) for k in range(n) for p, q in zip(a[k], b[k]))
    print("%d vertices compared (%d and %d in all): %.3g apart" % (n, len(a), len(b), worst))
    return 0 if worst <= tolerance else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
