#!/usr/bin/env python3
"""Writes the c_api fuzz target's seed corpus (fuzz/corpus/c_api): call sequences that load a scene,
build each exact structure and the field, query it, edit and commit the updatable ones, release
twice and call with stale handles. Bytes past each call's own are random (fixed seed), as rays."""

import os
import random

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "c_api")
SPECS = ["bvh", "bvh:levels=2", "bvh:leaf=1", "grid", "kdtree", "median-bsp", "brute", "beam:dirs=33,n=4", "field:positions=290,directions=8"]


def rays(rng, n):
    """n rays as the target reads them: six small coordinates (kind byte < 200, then a value) and a range byte."""
    out = []
    for _ in range(n):
        for _ in range(6):
            out += [rng.randrange(200), rng.randrange(256)]
        out.append(rng.randrange(200))
    return out


def main():
    os.makedirs(OUT, exist_ok=True)
    rng = random.Random(1)
    for k, spec in enumerate(SPECS):
        scene = [0, 0, 1, 1 + (k % 2)]  # scene call, slot 0, load, boxes or soup
        build = [2, 0, 0, k, 0]  # build from scene 0 into structure 0 with SPECS[k]
        query = [3, 0, 16, *rays(rng, 16), 0, 3, 0, 16, *rays(rng, 16), 1, 3, 0, 8, *rays(rng, 8), 2, 3, 0, 4, *rays(rng, 4), 3]
        edits = [5, 0, 1, 1, 0, 5, 0, 2, 3, 5, 0, 0, 0, 5, 0, 1, 2, 0, 5, 0, 0, 3, 3, 0, 16, *rays(rng, 16), 0]  # move, commit, remove, insert, commit
        release = [6, 1, 0, 1, 7, 0, 0, 3, 7, 1, 0, 0]  # release structure 0, then call it stale
        data = bytes(scene + build + query + edits + release)
        with open(os.path.join(OUT, f"seed-{k}-{spec.split(':')[0]}"), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
