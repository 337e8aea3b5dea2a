#!/usr/bin/python3
"""Writes seed inputs of the mesh_header fuzz target: a byte choosing the extension (0 ply, 1 stl,
2 glb, 3 gltf, 4 obj) followed by a small valid file of that format, plus the head of each shared
PLY model given (its header and the first bytes of its data).

Usage: fuzz/make_header_seeds.py OUT_FOLDER [MODEL.ply...]
"""
import base64
import json
import os
import struct
import sys

TRIANGLE = [0, 0, 0, 1, 0, 0, 0, 1, 0]


def ply(binary):
    fmt = "binary_little_endian" if binary else "ascii"
    head = ("ply\nformat %s 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n" % fmt).encode()
    if binary:
        return head + struct.pack("<9f", *TRIANGLE) + struct.pack("<B3i", 3, 0, 1, 2)
    return head + b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"


def gltf_json():
    data = struct.pack("<9f", *TRIANGLE) + struct.pack("<4H", 0, 1, 2, 0)
    return json.dumps({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}).encode()


def glb():
    text = gltf_json()
    text += b" " * (-len(text) % 4)
    return b"glTF" + struct.pack("<II", 2, 20 + len(text)) + struct.pack("<I", len(text)) + b"JSON" + text


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    seeds = {
        "ply-ascii": b"\0" + ply(False),
        "ply-binary": b"\0" + ply(True),
        "stl-binary": b"\1" + b"\0" * 80 + struct.pack("<I", 1) + struct.pack("<12fH", 0, 0, 1, *TRIANGLE, 0),
        "stl-ascii": b"\1" + b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                            b"endloop\nendfacet\nendsolid t\n",
        "glb": b"\2" + glb(),
        "gltf": b"\3" + gltf_json(),
        "obj": b"\4" + b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    }
    for model in sys.argv[2:]:
        with open(model, "rb") as f:
            seeds["head-" + os.path.basename(model)] = b"\0" + f.read(1024)
    for name, data in seeds.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
