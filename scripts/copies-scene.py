#!/usr/bin/python3
"""Writes a visfield scene file of many copies of one mesh: COUNT objects on a square grid in the
xz plane, SPACING world units apart, each turned by a random angle about +y and scaled by a random
factor in [0.8, 1.2] (seeded, so the same arguments give the same scene).
Used for the instancing measurements in the README; any mesh visfield reads works.

With --ground Y, the copies stand on a square ground at height Y (written beside OUT.json as
OUT-ground.obj and marked "occluder": "exact": a receiver that stays exact when the copies are
field objects), reaching one spacing past the grid on every side.

Usage: scripts/copies-scene.py MESH COUNT SPACING OUT.json [--seed S] [--ground Y]
"""
import argparse
import json
import math
import os
import random
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", help="mesh file (relative paths are taken from the output's folder)")
    parser.add_argument("count", type=int, help="number of copies (>= 1)")
    parser.add_argument("spacing", type=float, help="distance between neighbouring copies (> 0)")
    parser.add_argument("out", help="scene file to write (.json)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--ground", type=float, metavar="Y", help="add an exact ground at height Y")
    args = parser.parse_args()
    if args.count < 1 or not args.spacing > 0:
        sys.exit("copies-scene: error: count must be >= 1 and spacing > 0")

    rng = random.Random(args.seed)
    side = math.ceil(math.sqrt(args.count))
    mesh_path = os.path.relpath(os.path.abspath(args.mesh), os.path.dirname(os.path.abspath(args.out)))
    instances = []
    for i in range(args.count):
        instances.append({
            "mesh": "copy",
            "translate": [(i % side) * args.spacing, 0.0, (i // side) * args.spacing],
            "rotate_axis_angle": {"axis": [0, 1, 0], "degrees": rng.uniform(0.0, 360.0)},
            "scale": rng.uniform(0.8, 1.2),
        })
    scene = {"name": "%d copies of %s" % (args.count, os.path.basename(args.mesh)),
             "meshes": [{"name": "copy", "path": mesh_path}],
             "instances": instances}
    if args.ground is not None:
        lo, hi = -args.spacing, side * args.spacing
        ground = os.path.splitext(args.out)[0] + "-ground.obj"
        with open(ground + ".tmp", "w") as f:
            f.write("# the ground of %s\n" % os.path.basename(args.out))
            for x, z in ((lo, lo), (hi, lo), (hi, hi), (lo, hi)):
                f.write("v %r %r %r\n" % (x, args.ground, z))
            f.write("f 1 4 3\nf 1 3 2\n")  # facing +y
        os.replace(ground + ".tmp", ground)
        scene["meshes"].append({"name": "ground", "path": os.path.basename(ground), "occluder": "exact"})
        scene["instances"].append({"mesh": "ground"})
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(scene, f, indent=1)
    os.replace(tmp, args.out)


if __name__ == "__main__":
    main()
