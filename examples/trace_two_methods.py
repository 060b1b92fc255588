"""Trace the bunny with two methods from Python and plot where their depths differ.

    PYTHONPATH=build/python /usr/bin/python3 examples/trace_two_methods.py \
        [data/bunny/bunny.ply] [out/two_methods.png]

A pinhole camera's primary rays are traced with reference_splat (discs on a kd-tree) and
goradia_2010 (MLS projection on an octree); the plot shows both depth maps and their difference
in units of the cloud's bounding-box diagonal.
"""
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pcrt  # noqa: E402

data = sys.argv[1] if len(sys.argv) > 1 else "data/bunny/bunny.ply"
out = sys.argv[2] if len(sys.argv) > 2 else "out/two_methods.png"
cloud = pcrt.load(data)
lo, hi = (np.array(b) for b in cloud.bounds)
centre, diagonal = (lo + hi) / 2, np.linalg.norm(hi - lo)

# The bunny is y-up: camera on the +z side looking at the centre, a 40 degree field of view, 320 x 320 rays.
width = height = 320
eye = centre + diagonal * np.array([0.3, 0.3, 1.4])
forward = (centre - eye) / np.linalg.norm(centre - eye)
right = np.cross(forward, [0, 1.0, 0])
right /= np.linalg.norm(right)
up = np.cross(right, forward)
half = np.tan(np.radians(20))
u, v = np.meshgrid(np.linspace(-half, half, width), np.linspace(half, -half, height))
directions = forward + u[..., None] * right + v[..., None] * up
directions = directions.reshape(-1, 3).astype(np.float32)
origins = np.broadcast_to(eye, directions.shape).astype(np.float32)

depth = {}
for method, structure in (("reference_splat", "kd_tree"), ("goradia_2010", "octree")):
    scene = pcrt.Scene(cloud, method=method, structure=structure)
    start = time.perf_counter()
    hits = scene.trace(origins, directions)
    seconds = time.perf_counter() - start
    depth[method] = np.where(hits["hit"], hits["t"], np.nan).reshape(height, width)
    print(f"{method} on {structure}: {hits['hit'].mean():.1%} of {len(origins)} rays hit, "
          f"{seconds:.3f} s, {scene.counters['nodes_visited']} nodes visited")

a, b = depth["reference_splat"], depth["goradia_2010"]
difference = (b - a) / diagonal
fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
for ax, (title, image, cmap) in zip(axes, [("reference_splat depth", a, "viridis"),
                                           ("goradia_2010 depth", b, "viridis"),
                                           ("difference / diagonal", difference, "coolwarm")]):
    limit = np.nanmax(np.abs(difference)) if cmap == "coolwarm" else None
    shown = ax.imshow(image, cmap=cmap, vmin=-limit if limit else None, vmax=limit)
    ax.set_title(title)
    ax.axis("off")
    fig.colorbar(shown, ax=ax, shrink=0.8)
fig.tight_layout()
fig.savefig(out, dpi=100)
both = np.isfinite(difference)
print(f"{out}: where both hit, |difference| median {np.median(np.abs(difference[both])):.2e}, "
      f"99th percentile {np.percentile(np.abs(difference[both]), 99):.2e} of the diagonal; "
      f"hit by one method only: {int((np.isfinite(a) != np.isfinite(b)).sum())} rays")
