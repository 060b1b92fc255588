#!/usr/bin/env python3
"""The caustic under a glass point-cloud bunny (issue 34): goradia_2011's caustic sample map
against the same rays path traced (kashyap_2010_implicit: the same intersection, no map) and
against the exact mesh, converged.

The scene: scenes/caustic_bunny*.json, a glass bunny (10^5 points sampled on the npm bunny, or
its triangles on Embree) on a mesh floor under a small sphere light. Frames, all B = 8:
  goradia_2011, kashyap_2010_implicit, the mesh   at --spp (seed 1): the frames compared
  reference/caustic_bunny_mesh.exr                the mesh at --ref-spp (seed 2): committed
  a check frame                                   the mesh at --ref-spp / 4 (seed 3): the
      reference's own noise is RMSE(check - reference) / sqrt(5) (variance 1 : 4, independent)
Against the reference, over the floor's pixels (where the caustic lands) and over the frame:
RMSE, relMSE ((v - ref)^2 / (ref^2 + 0.01), the mean over pixels and channels), and the floor's
mean radiance over the reference's (energy: a path tracer's noise keeps it in expectation, a
density estimate's blur should too). The mesh at --spp is what unidirectional path tracing of
the exact surface gives at the same samples: kashyap_2010_implicit cannot do better.

Writes OUT/caustic_bunny.png (goradia_2011 | kashyap_2010_implicit | mesh reference),
OUT/table.md, OUT/metrics.json and each frame's --stats JSON.
Usage: PYTHONPATH=build/python scripts/caustics.py [--pcrt build/bin/pcrt] [--out DIR]
"""
import argparse
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import pcrt

sys.path.insert(0, str(Path(__file__).resolve().parent))
from specular_error import rgb  # noqa: E402  (an EXR's RGB as float64)

HERE = Path(__file__).resolve().parent.parent
SCENES = {"goradia_2011": "caustic_bunny", "kashyap_2010_implicit": "caustic_bunny_kashyap",
          "mesh": "caustic_bunny_mesh"}


def render(args, scene, out, spp, seed, bounces, extra=()):
    """Renders scenes/SCENE.json to `out`, returns the frame's --stats JSON (written beside it)."""
    stats = out.with_suffix(".stats.json")
    subprocess.run([args.pcrt, "render", "--scene", str(HERE / "scenes" / f"{scene}.json"),
                    "--out", str(out), "--width", str(args.width), "--height", str(args.height),
                    "--spp", str(spp), "--bounces", str(bounces), "--seed", str(seed),
                    "--threads", str(args.threads), "--stats", str(stats), *extra],
                   check=True, stdout=subprocess.DEVNULL)
    return json.loads(stats.read_text())


def srgb(v):
    """As pcrt writes a PNG: clipped to [0, 1], the sRGB curve."""
    v = np.clip(v, 0, 1)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def floor_mask(args, tmp):
    """The pixels whose camera ray meets the floor first: hit in the mesh scene, and not where
    the bunny alone is hit at the same depth."""
    depth = {}
    for name, scene in (("scene", "caustic_bunny_mesh"), ("bunny", None)):
        if scene is None:  # the bunny alone: the mesh scene without its floor
            spec = json.loads((HERE / "scenes/caustic_bunny_mesh.json").read_text())
            spec["objects"] = [o for o in spec["objects"] if o["name"] == "bunny"]
            spec["objects"][0]["mesh"] = str(HERE / "data/bunny/bunny.off")
            scene = tmp / "bunny_alone"
            scene.with_suffix(".json").write_text(json.dumps(spec))
        z = tmp / f"{name}.depth.exr"
        render(args, scene, tmp / f"{name}.exr", 1, 1, 0, ("--depth", str(z)))
        depth[name] = pcrt.read_exr(str(z))["Z"]
    z, zb = depth["scene"], depth["bunny"]
    with np.errstate(invalid="ignore"):  # inf - inf where both miss
        bunny = np.isfinite(zb) & (np.abs(zb - z) <= 1e-4 * np.maximum(z, 1))
    return np.isfinite(z) & ~bunny


def errors(v, ref, floor):
    d = v - ref
    rel = d * d / (ref * ref + 0.01)
    return {"rmse_floor": float(np.sqrt(np.mean(d[floor] ** 2))),
            "relmse_floor": float(np.mean(rel[floor])),
            "rmse": float(np.sqrt(np.mean(d * d))), "relmse": float(np.mean(rel)),
            "floor_mean_ratio": float(v[floor].mean() / ref[floor].mean())}


def figure(path, frames, labels):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    h, w = frames[0].shape[:2]
    fig, axes = plt.subplots(1, len(frames), figsize=(len(frames) * w / 100, h / 100 + 0.3))
    for ax, im, label in zip(axes, frames, labels):
        ax.imshow(srgb(im), interpolation="nearest")
        ax.set_title(label, fontsize=8)
        ax.axis("off")
    fig.tight_layout(pad=0.2)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def reference(args, tmp):
    """The converged mesh frame (OUT/reference) and its own noise."""
    path = args.out / "reference" / "caustic_bunny_mesh.exr"
    path.parent.mkdir(parents=True, exist_ok=True)
    stats = render(args, "caustic_bunny_mesh", path, args.ref_spp, 2, args.bounces)
    render(args, "caustic_bunny_mesh", tmp / "check.exr", args.ref_spp // 4, 3, args.bounces)
    ref = rgb(path)
    noise = float(np.sqrt(np.mean((rgb(tmp / "check.exr") - ref) ** 2)) / math.sqrt(5))
    return ref, stats["timings"]["render"], noise


def saved_reference(args):
    """The reference and its noise as the last run wrote them (OUT/reference, OUT/metrics.json):
    the mesh frame does not change with the point methods, so a rerun need not converge it."""
    path, metrics = args.out / "reference" / "caustic_bunny_mesh.exr", args.out / "metrics.json"
    if not path.exists() or not metrics.exists():
        sys.exit(f"caustics: --reuse-reference: {path} or {metrics} is missing")
    run = json.loads(metrics.read_text())
    for key in ("width", "height", "ref_spp", "bounces"):
        if run["settings"].get(key) != str(getattr(args, key)):
            sys.exit(f"caustics: --reuse-reference: {metrics} has {key} "
                     f"{run['settings'].get(key)}, this run {getattr(args, key)}")
    return rgb(path), run["reference_seconds"], run["reference_noise_rmse"]


def write_table(args, rows, ref_seconds, noise):
    lines = [f"{args.width}x{args.height}, B = {args.bounces}, {args.threads} threads: frames at "
             f"S = {args.spp} (seed 1) against the mesh at S = {args.ref_spp} (seed 2, "
             f"{ref_seconds:.0f} s; its own noise from a second frame at S = {args.ref_spp // 4}: "
             f"RMSE {noise:.4f}). Floor: the pixels whose camera ray meets the floor first.", "",
             "| frame | RMSE, floor | relMSE, floor | floor mean / reference's | RMSE | relMSE "
             "| render s (prepass s) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['frame']} | {r['rmse_floor']:.4f} | {r['relmse_floor']:.4f} | "
                     f"{r['floor_mean_ratio']:.3f} | {r['rmse']:.4f} | {r['relmse']:.4f} | "
                     f"{r['seconds']:.1f} ({r['csm_seconds']:.1f}) |")
    (args.out / "table.md").write_text("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pcrt", default=str(HERE / "build/bin/pcrt"))
    ap.add_argument("--out", type=Path, default=HERE / "results/caustics")
    ap.add_argument("--width", type=int, default=400)
    ap.add_argument("--height", type=int, default=300)
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--ref-spp", type=int, default=16384)
    ap.add_argument("--bounces", type=int, default=8)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reuse-reference", action="store_true",
                    help="keep OUT/reference and its noise from the last run (same size, S, B)")
    args = ap.parse_args()
    if args.ref_spp < 4 or args.spp < 1:
        sys.exit(f"caustics: --ref-spp {args.ref_spp} / --spp {args.spp}: need >= 4 and >= 1")
    args.out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        floor = floor_mask(args, tmp)
        ref, ref_seconds, noise = (saved_reference(args) if args.reuse_reference
                                   else reference(args, tmp))
        rows, frames = [], {}
        for frame, scene in SCENES.items():
            stats = render(args, scene, tmp / f"{scene}.exr", args.spp, 1, args.bounces)
            (args.out / f"{scene}.stats.json").write_text(json.dumps(stats, indent=2) + "\n")
            frames[frame] = rgb(tmp / f"{scene}.exr")
            rows.append({"frame": frame, **errors(frames[frame], ref, floor),
                         "seconds": stats["timings"]["render"],
                         "csm_seconds": stats["timings"].get("csm", 0.0)})
    figure(args.out / "caustic_bunny.png",
           [frames["goradia_2011"], frames["kashyap_2010_implicit"], ref],
           [f"goradia_2011 (caustic sample map), S = {args.spp}",
            f"kashyap_2010_implicit (paths only), S = {args.spp}",
            f"exact mesh, S = {args.ref_spp}"])
    write_table(args, rows, ref_seconds, noise)
    (args.out / "metrics.json").write_text(json.dumps(
        {"rows": rows, "reference_seconds": ref_seconds, "reference_noise_rmse": noise,
         "floor_pixels": int(floor.sum()),
         "settings": {k: str(v) for k, v in vars(args).items() if k not in ("pcrt", "out")}},
        indent=2) + "\n")
    print(f"caustics: {args.out}/caustic_bunny.png, {args.out}/table.md")


if __name__ == "__main__":
    main()
