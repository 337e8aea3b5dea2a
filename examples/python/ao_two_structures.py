"""Ambient occlusion of a mesh through two structures, and their speed side by side.

    python3 examples/python/ao_two_structures.py MODEL.ply [--accel bvh kdtree] [--size 256] [--out ao-speed.png]

Renders the same AO image through each structure (the images are identical: both are exact),
times the renders, writes the image and a bar chart of rays per second (matplotlib).
"""

import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import visfield as vf  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", help="a mesh file, a scene .json or builtin:NAME")
    parser.add_argument("--accel", nargs="+", default=["bvh", "kdtree"], help="structures to compare (specs)")
    parser.add_argument("--size", type=int, default=256, help="image width and height in pixels")
    parser.add_argument("--ao-rays", type=int, default=32)
    parser.add_argument("--out", default="ao-speed.png", help="the bar chart; the AO image goes beside it as ao.png")
    args = parser.parse_args()

    scene = vf.load(args.model)
    speeds, images = [], []
    for spec in args.accel:
        renderer = vf.Renderer(scene, accel=spec)
        renderer.render(width=32, height=32, ao_rays=args.ao_rays)  # warm-up: threads and caches
        image, stats = renderer.render(width=args.size, height=args.size, ao_rays=args.ao_rays, stats=True)
        images.append(image)
        speeds.append(stats["rays"] / stats["seconds"] / 1e6)
        print(f"{renderer.accel}: build {renderer.build_ms:.1f} ms, render {stats['seconds']:.3f} s, "
              f"{stats['rays']:,} rays, {speeds[-1]:.1f} Mrays/s")
    for spec, image in zip(args.accel[1:], images[1:]):
        print(f"{spec} vs {args.accel[0]}: {'the same image' if np.array_equal(image, images[0]) else 'images differ'}")

    vf.write_image(os.path.join(os.path.dirname(args.out), "ao.png"), images[0])
    figure, axes = plt.subplots(figsize=(5, 3))
    axes.bar(args.accel, speeds, color="#4c72b0")
    axes.set_ylabel("million rays per second")
    axes.set_title(f"AO of {scene.name} ({args.size}x{args.size}, {args.ao_rays} rays/pixel)", fontsize=9)
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
