"""An ObjectField's error, seen: the exact AO render, the render through fields, and their
difference x5 side by side (as the fields papers show it).

    python3 examples/python/field_error.py MODEL.ply [--positions 4226] [--directions 32] [--out field-error.png]

The model stands on a ground made here from NumPy arrays and kept exact; every AO ray (the
ground's and the model's own) meets the model through its field, in the second render.
"""

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import visfield as vf  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", help="a mesh file")
    parser.add_argument("--positions", type=int, default=4226, choices=[290, 1090, 4226, 16642])
    parser.add_argument("--directions", type=int, default=32)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--ao-rays", type=int, default=64)
    parser.add_argument("--out", default="field-error.png")
    args = parser.parse_args()

    scene = vf.load(args.model)
    lo, hi = scene.bounds
    centre, size = (lo + hi) / 2, float((hi - lo).max())
    # A ground square under the model, four times its size, exact whatever the render's occluders.
    g = 2 * size
    ground = np.array([[centre[0] - g, lo[1], centre[2] - g], [centre[0] + g, lo[1], centre[2] - g],
                       [centre[0] + g, lo[1], centre[2] + g], [centre[0] - g, lo[1], centre[2] + g]], dtype=np.float32)
    scene.add_instance(scene.add_mesh(ground, np.array([[0, 2, 1], [0, 3, 2]]), occluder="exact"))
    camera = scene.camera(args.size, args.size)
    camera.look_at = centre.tolist()
    camera.position = (centre + np.array([0.9, 0.7, 1.5]) * size).tolist()
    field = vf.Field.build(scene, 0, positions=args.positions, directions=args.directions)
    print(f"field: {field.positions} positions x {field.directions}^2, {field.memory_bytes / 2**20:.2f} MiB, "
          f"precomputed in {field.build_ms / 1000:.2f} s")
    settings = dict(camera=camera, ao_rays=args.ao_rays, max_distance=size)
    exact = vf.render(scene, **settings)
    spec = f"field:positions={args.positions},directions={args.directions}"
    approximate = vf.render(scene, occluder=spec, occluders="field", **settings)
    difference = vf.compare(approximate, exact)
    print(f"RMS {difference['rms_255']:.2f} (0-255), PSNR {difference['psnr_db']:.1f} dB")

    error = np.clip(5 * np.abs(approximate - exact), 0, 1)
    figure, axes = plt.subplots(1, 3, figsize=(9, 3.3))
    for ax, image, title in zip(axes, [exact, approximate, error], ["exact", f"{field.positions} x {field.directions}²", "|difference| x 5"]):
        ax.imshow(np.clip(image, 0, 1))
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    figure.suptitle(f"AO through an ObjectField: RMS {difference['rms_255']:.2f} of 255", fontsize=10)
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
