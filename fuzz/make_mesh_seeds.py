#!/usr/bin/python3
"""Writes seed inputs of the mesh_import fuzz target from OBJ files: the first (up to) 63 vertices of
each file and the faces among its first 200 that use only those, encoded in the target's format
(see fuzz/targets/mesh_import.cpp), plus one seed with a material and a transformed child node.

Usage: fuzz/make_mesh_seeds.py OUT_FOLDER MODEL.obj...
"""
import os
import struct
import sys


def read_obj(path, max_vertices=63, max_faces=200):
    vertices, faces = [], []
    with open(path, errors="replace") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v" and len(vertices) < max_vertices:
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f" and len(faces) < max_faces:
                face = [int(p.split("/")[0]) - 1 for p in parts[1:]]
                if all(0 <= i < max_vertices for i in face):
                    faces.append(face)
    faces = [f for f in faces if all(i < len(vertices) for i in f)][:63]
    return vertices, faces


def encode(vertices, faces, material=None, child_transform=None):
    out = bytearray()
    out += bytes([1 if material else 0])                     # use_materials
    out += bytes([1 if material else 0])                     # materials
    if material:
        out += bytes([1 | 2 | 8]) + struct.pack("<4f", *material)
    out += bytes([1])                                        # meshes
    out += bytes([len(vertices)]) + b"".join(struct.pack("<3f", *v) for v in vertices)
    out += bytes([len(faces)])
    for f in faces:
        out += bytes([len(f)]) + b"".join(struct.pack("<H", i) for i in f)
    out += bytes([0])                                        # material index
    out += bytes([0, 1, 0, 1 if child_transform else 0])     # root: identity, mesh 0, children
    if child_transform:
        out += bytes([1]) + struct.pack("<16f", *child_transform) + bytes([1, 0, 0])
    return bytes(out)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for path in sys.argv[2:]:
        vertices, faces = read_obj(path)
        name = os.path.splitext(os.path.basename(path))[0]
        with open(os.path.join(out, name), "wb") as f:
            f.write(encode(vertices, faces))
    quad = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    moved = [2, 0, 0, 1, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1]
    with open(os.path.join(out, "quad-material-child"), "wb") as f:
        f.write(encode(quad, [[0, 1, 2, 3]], material=[0.5, 0.2, 0.1, 40.0], child_transform=moved))


if __name__ == "__main__":
    main()
