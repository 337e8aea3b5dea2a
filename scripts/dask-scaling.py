"""Dask scaling of visfield.distributed on this machine: the same AO image rendered in tiles by a
LocalCluster of 1 and then 2 worker processes (one thread each, visfield limited to one thread per
worker), after a warm-up that loads the scene and builds its structures on every worker.

    PYTHONPATH=build/python /usr/bin/python3 scripts/dask-scaling.py SCENE [--size 512] [--ao-rays 64] [--tile 64]
"""

import argparse
import time

import numpy as np
from distributed import Client, LocalCluster

import visfield as vf
import visfield.distributed as vfd


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--ao-rays", type=int, default=64)
    parser.add_argument("--tile", type=int, default=64)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    settings = dict(width=args.size, height=args.size, ao_rays=args.ao_rays, tile=args.tile)

    vf.set_threads(1)
    start = time.perf_counter()
    reference = vf.render(vf.load(args.scene), width=args.size, height=args.size, ao_rays=args.ao_rays)
    print(f"one process, one thread, no Dask: {time.perf_counter() - start:.2f} s (load, build, render)")

    times = {}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(vf.set_threads, 1)
            vfd.render_tiles(client, args.scene, **settings)  # warm-up: every worker loads and builds once
            best = float("inf")
            for _ in range(args.repeats):
                start = time.perf_counter()
                image = vfd.render_tiles(client, args.scene, **settings)
                best = min(best, time.perf_counter() - start)
            assert np.array_equal(image, reference), "the distributed image differs from the single-machine one"
            times[workers] = best
            print(f"{workers} worker(s): {best:.3f} s per image (best of {args.repeats}), identical to one machine")
    print(f"speed-up 1 -> 2 workers: {times[1] / times[2]:.2f}x")


if __name__ == "__main__":
    main()
