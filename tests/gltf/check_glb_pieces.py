#!/usr/bin/env python3
"""Decodes each Draco primitive of a GLB in pieces with Draco's own
draco_decoder and checks that no crack opens: every vertex on a border
decodes to the same bits in each piece that holds it, so the pieces'
distinct positions are as many as the mesh's vertices.
Usage: check_glb_pieces.py FILE.glb PIECES VERTICES"""
import json
import os
import struct
import subprocess
import sys
import tempfile


def glb_chunks(data):
    json_length = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + json_length])
    bin_at = 20 + json_length
    bin_length = struct.unpack_from("<I", data, bin_at)[0]
    return doc, data[bin_at + 8:bin_at + 8 + bin_length]


def ply_positions(path):
    """x, y, z of every vertex of a PLY draco_decoder wrote (ASCII or binary)."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    fmt = header[1].split()[1]
    count, props = 0, []
    in_vertex = False
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count, in_vertex = int(words[2]), True
        elif words and words[0] == "element":
            in_vertex = False
        elif in_vertex and words[0] == "property":
            props.append(words[1])
    assert props[:3] == ["float"] * 3, props
    if fmt == "ascii":
        lines = data[end:].decode().splitlines()[:count]
        return [tuple(struct.unpack("<f", struct.pack("<f", float(v)))[0] for v in l.split()[:3])
                for l in lines]
    sizes = {"float": 4, "uchar": 1, "char": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4}
    stride = sum(sizes[p] for p in props)
    return [struct.unpack_from("<fff", data, end + k * stride) for k in range(count)]


def main():
    path, pieces, vertices = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    doc, binary = glb_chunks(open(path, "rb").read())
    prims = doc["meshes"][0]["primitives"]
    if len(prims) != pieces:
        sys.exit(f"{path}: {len(prims)} primitives, expected {pieces}")
    seen, total = set(), 0
    with tempfile.TemporaryDirectory() as tmp:
        for k, prim in enumerate(prims):
            view = doc["bufferViews"][prim["extensions"]["KHR_draco_mesh_compression"]["bufferView"]]
            start = view.get("byteOffset", 0)
            drc = os.path.join(tmp, f"{k}.drc")
            ply = os.path.join(tmp, f"{k}.ply")
            open(drc, "wb").write(binary[start:start + view["byteLength"]])
            subprocess.run(["draco_decoder", "-i", drc, "-o", ply], check=True,
                           stdout=subprocess.DEVNULL)
            points = ply_positions(ply)
            total += len(points)
            seen.update(points)
    if total <= vertices:
        sys.exit(f"{path}: {total} decoded vertices; the pieces share none (no borders?)")
    if len(seen) != vertices:
        sys.exit(f"{path}: {len(seen)} distinct decoded positions for {vertices} vertices: "
                 "a border decoded differently in two pieces (a crack)")
    print(f"{path}: {pieces} pieces by draco_decoder, {total} vertices decoded, "
          f"{len(seen)} distinct: no crack")


if __name__ == "__main__":
    main()
