#!/usr/bin/env python3
"""Image error where light bounces: every method's frame of a mirror, a glass and a glossy bunny
against the same bunny as an exact mesh, converged (issue 34).

The scene: the npm bunny (10^5 points sampled on it for the methods, its triangles on Embree for
the reference) in a box of a grey floor and red, green and white walls under a sphere light and
a dim sky, so that what a specular bunny shows has edges and colours. Per material:
  reference/MATERIAL.exr   the mesh at --ref-spp (seed 1): the converged frame, committed
  a check frame            the mesh at --ref-spp / 4 (seed 2): the reference's own noise is
                           RMSE(check - reference) / sqrt(5) (independent noise, variance 1 : 4)
  each method and the mesh at --spp (seed 3): RMSE, relMSE ((v - ref)^2 / (ref^2 + 0.01), the
  mean over pixels and channels) and SSIM (scikit-image, on the frames clipped to [0, 1] with a
  2.2 gamma); the mesh's own row at --spp is the noise floor a method cannot go below.
The normal error: each method's primary-hit normals against the mesh's on the same camera
(the bunny alone, one sample per pixel), the angle between them and between the camera ray's
mirror reflections off them, per pixel where both hit: the reflection's amplification measured.

Writes OUT/table.md, OUT/metrics.json, OUT/reference/*.exr, OUT/sheet_MATERIAL.png and
OUT/error_vs_normal.png.
Usage: PYTHONPATH=build/python scripts/specular_error.py [--pcrt build/bin/pcrt] [--out DIR]
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

HERE = Path(__file__).resolve().parent.parent
BUNNY = HERE / "data/bunny/bunny.off"
MATERIALS = {
    "mirror": {"type": "mirror"},
    "glass": {"type": "dielectric", "eta": 1.5},
    "glossy": {"type": "rough_conductor", "roughness": 0.15},
}
# Brute-force defaults trace on the kd-tree instead: the same hits, in seconds (as the contact
# sheets of `pcrt compare` do).
STRUCTURE = {"reference_splat": "kd_tree", "tejada_2006": "kd_tree"}
CAMERA = {"eye": [6, -26, 11], "target": [0, 0, 4], "up": [0, 0, 1], "fov": 34}
BUNNY_PLACE = {"rotate": {"axis": [1, 0, 0], "degrees": 90}, "translate": [0, 0, -0.05]}


def wall(name, material, rotate, translate):
    return {"name": name, "quad": {"size": 40}, "engine": "bvh", "material": material,
            "transform": {"rotate": rotate, "translate": translate}}


def bunny_object(method, material):
    """The bunny: the exact mesh on Embree (method None) or 10^5 points sampled on it."""
    place = {"name": "bunny", "material": material, "transform": BUNNY_PLACE}
    if method is None:
        return {**place, "mesh": str(BUNNY), "engine": "embree"}
    obj = {**place, "sample": str(BUNNY), "sampling": "n=100000,seed=1", "method": method}
    if method in STRUCTURE:
        obj["structure"] = STRUCTURE[method]
    return obj


def box_scene(method, material):
    return {
        "materials": {"bunny": MATERIALS[material],
                      "floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                      "red": {"type": "diffuse", "albedo": [0.7, 0.12, 0.1]},
                      "green": {"type": "diffuse", "albedo": [0.12, 0.6, 0.15]},
                      "white": {"type": "diffuse", "albedo": [0.75, 0.75, 0.72]}},
        "objects": [bunny_object(method, "bunny"),
                    {"name": "floor", "quad": {"size": 60}, "engine": "bvh", "material": "floor"},
                    wall("back", "white", {"axis": [1, 0, 0], "degrees": 90}, [0, 14, 20]),
                    wall("left", "red", {"axis": [0, 1, 0], "degrees": 90}, [-14, 0, 20]),
                    wall("right", "green", {"axis": [0, 1, 0], "degrees": -90}, [14, 0, 20])],
        "lights": [{"type": "sphere", "position": [-6, -12, 24], "radius": 5, "radiance": 9},
                   {"type": "environment", "radiance": [0.08, 0.09, 0.11]}],
        "camera": CAMERA,
    }


def normals_scene(method):
    """The bunny alone, diffuse: its primary-hit normals."""
    return {"materials": {"grey": {"type": "diffuse"}},
            "objects": [bunny_object(method, "grey")],
            "lights": [{"type": "environment", "radiance": 1}], "camera": CAMERA}


def render(args, scene, out, spp, seed, bounces, extra=()):
    """Renders a scene dict to `out` (an .exr), returns the frame's --stats JSON."""
    scene_file, stats = out.with_suffix(".scene.json"), out.with_suffix(".stats.json")
    scene_file.write_text(json.dumps(scene))
    subprocess.run([args.pcrt, "render", "--scene", str(scene_file), "--out", str(out),
                    "--width", str(args.width), "--height", str(args.height), "--spp", str(spp),
                    "--bounces", str(bounces), "--seed", str(seed), "--threads",
                    str(args.threads), "--stats", str(stats), *extra],
                   check=True, stdout=subprocess.DEVNULL)
    return json.loads(stats.read_text())


def rgb(path):
    c = pcrt.read_exr(str(path))
    return np.stack([c["R"], c["G"], c["B"]], axis=-1).astype(np.float64)


def display(v):
    return np.clip(v, 0, 1) ** (1 / 2.2)


def image_error(v, ref, bunny):
    """RMSE, relMSE and SSIM over the frame, and relMSE over the bunny's own pixels."""
    from skimage.metrics import structural_similarity
    d = v - ref
    rel = d * d / (ref * ref + 0.01)
    return {"rmse": float(np.sqrt(np.mean(d * d))), "relmse": float(np.mean(rel)),
            "relmse_bunny": float(np.mean(rel[bunny])),
            "ssim": float(structural_similarity(display(v), display(ref), channel_axis=2,
                                                data_range=1.0))}


def camera_directions(w, h):
    """The camera rays through the pixel centres, as core/camera.hpp makes them."""
    eye, target, up = (np.array(CAMERA[k], float) for k in ("eye", "target", "up"))
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = math.tan(0.5 * math.radians(CAMERA["fov"]))
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    sx, sy = (2 * x / w - 1) * t * w / h, (1 - 2 * y / h) * t
    d = f + sx[..., None] * r + sy[..., None] * u
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def facing(n, d):
    """Unit normals turned towards the camera."""
    n = n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-30)
    return np.where((n * d).sum(-1, keepdims=True) > 0, -n, n)


def angle_deg(a, b):
    return np.degrees(np.arccos(np.clip((a * b).sum(-1), -1, 1)))


def normal_error(args, tmp, method, ref_n, ref_z):
    """Median and 95th percentile of the normal's and the mirrored ray's angle errors."""
    out = tmp / f"n.{method}.exr"
    render(args, normals_scene(method), out, 1, 1, 0,
           ("--normals", str(tmp / f"n.{method}.normals.exr"), "--depth",
            str(tmp / f"n.{method}.depth.exr")))
    z = pcrt.read_exr(str(tmp / f"n.{method}.depth.exr"))["Z"]
    n = rgb(tmp / f"n.{method}.normals.exr")
    d = camera_directions(args.width, args.height)
    both = np.isfinite(z) & np.isfinite(ref_z)
    nm, nr = facing(n, d)[both], facing(ref_n, d)[both]
    dd = d[both]
    reflect = lambda nn: dd - 2 * (dd * nn).sum(-1, keepdims=True) * nn
    dn, dr = angle_deg(nm, nr), angle_deg(reflect(nm), reflect(nr))
    return {"pixels": int(both.sum()), "normal_median_deg": float(np.median(dn)),
            "normal_p95_deg": float(np.percentile(dn, 95)),
            "reflection_median_deg": float(np.median(dr)),
            "reflection_p95_deg": float(np.percentile(dr, 95)),
            "amplification": float(np.median(dr) / max(np.median(dn), 1e-12))}


def references(args, tmp):
    """Per material the converged mesh frame (written to OUT/reference) and its noise."""
    refs = {}
    for mat in MATERIALS:
        path = args.out / "reference" / f"{mat}.exr"
        stats = render(args, box_scene(None, mat), path, args.ref_spp, 1, args.bounces)
        render(args, box_scene(None, mat), tmp / f"check.{mat}.exr", args.ref_spp // 4, 2,
               args.bounces)
        ref, check = rgb(path), rgb(tmp / f"check.{mat}.exr")
        refs[mat] = {"image": ref, "seconds": stats["timings"]["render"],
                     "noise_rmse": float(np.sqrt(np.mean((check - ref) ** 2)) / math.sqrt(5))}
        path.with_suffix(".scene.json").unlink()
    return refs


def saved_references(args):
    """The references a previous run wrote (OUT/reference/*.exr, their noise in OUT/metrics.json):
    a frame of the exact mesh does not change with the point methods, so a rerun after a
    method's change need not converge them again."""
    metrics = args.out / "metrics.json"
    if not metrics.exists():
        sys.exit(f"specular_error: --reuse-references: {metrics} is missing")
    run = json.loads(metrics.read_text())
    for key in ("width", "height", "ref_spp", "bounces"):
        if run["settings"].get(key) != getattr(args, key):
            sys.exit(f"specular_error: --reuse-references: {metrics} has {key} "
                     f"{run['settings'].get(key)}, this run {getattr(args, key)}")
    saved, refs = run["reference"], {}
    for mat in MATERIALS:
        path = args.out / "reference" / f"{mat}.exr"
        if not path.exists() or mat not in saved:
            sys.exit(f"specular_error: --reuse-references: {path} or its entry is missing")
        refs[mat] = {**saved[mat], "image": rgb(path)}
    return refs


def frame_row(args, tmp, mat, method, ref, bunny):
    """One frame at --spp against the reference: its errors, time and rays."""
    out = tmp / f"{mat}.{method or 'mesh'}.exr"
    stats = render(args, box_scene(method, mat), out, args.spp, 3, args.bounces)
    v = rgb(out)
    row = {"material": mat, "method": method or "mesh (noise floor)", **image_error(v, ref, bunny),
           "seconds": stats["timings"]["render"], "rays": stats["counters"].get("rays_cast", 0)}
    return row, v


def sheet(path, images, labels, cols=5):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = (len(images) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(2.4 * cols, 2.0 * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, im, label in zip(axes.flat, images, labels):
        ax.imshow(display(im))
        ax.set_title(label, fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def relation_plot(path, rows, normals):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(MATERIALS), figsize=(4 * len(MATERIALS), 3.4))
    for ax, mat in zip(axes, MATERIALS):
        pts = [(normals[r["method"]]["normal_median_deg"], r["relmse_bunny"], r["method"])
               for r in rows if r["material"] == mat and r["method"] in normals]
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=12)
        for x, y, m in pts:
            ax.annotate(m.split("_")[0], (x, y), fontsize=5)
        ax.set_xscale("log")
        ax.set_xlabel("median normal error at primary hits (degrees)")
        ax.set_ylabel("relMSE of the bunny's pixels")
        ax.set_title(mat, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def spearman(x, y):
    rank = lambda v: np.argsort(np.argsort(v)).astype(float)
    return float(np.corrcoef(rank(np.array(x)), rank(np.array(y)))[0, 1])


def write_table(args, refs, rows, normals):
    lines = [f"Frames {args.width}x{args.height}, B = {args.bounces}: methods at S = {args.spp} "
             f"(seed 3), the reference at S = {args.ref_spp} (seed 1). `normal` / `reflection`: "
             "median angle errors at primary hits against the mesh (degrees), and their ratio.", ""]
    for mat in MATERIALS:
        lines += [f"## {mat}", "",
                  f"Reference: {refs[mat]['seconds']:.0f} s; its own noise, estimated from a "
                  f"second frame at S = {args.ref_spp // 4}: RMSE {refs[mat]['noise_rmse']:.4f}.",
                  "", "| method | RMSE | relMSE | relMSE of the bunny pixels (minus the mesh row's) | SSIM "
                  "| normal | reflection | ratio | s |", "|---|---|---|---|---|---|---|---|---|"]
        mine = [r for r in rows if r["material"] == mat]
        floor = next(r for r in mine if r["method"].startswith("mesh"))["relmse_bunny"]
        for r in sorted(mine, key=lambda r: r["relmse"]):
            n = normals.get(r["method"])
            ncells = (f"{n['normal_median_deg']:.3g} | {n['reflection_median_deg']:.3g} | "
                      f"{n['amplification']:.2f}") if n else " | | "
            lines.append(f"| {r['method']} | {r['rmse']:.4f} | {r['relmse']:.4f} | "
                         f"{r['relmse_bunny']:.4f} ({r['relmse_bunny'] - floor:+.4f}) | "
                         f"{r['ssim']:.4f} | {ncells} | {r['seconds']:.1f} |")
        methods = [r for r in mine if r["method"] in normals]
        rho = spearman([normals[r["method"]]["normal_median_deg"] for r in methods],
                       [r["relmse_bunny"] for r in methods])
        lines += ["", f"Spearman rank correlation of the bunny pixels' relMSE with the median "
                  f"normal error over "
                  f"{len(methods)} methods: {rho:.2f}.", ""]
    (args.out / "table.md").write_text("\n".join(lines) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--pcrt", default=str(HERE / "build/bin/pcrt"))
    p.add_argument("--out", type=Path, default=HERE / "results/specular")
    p.add_argument("--methods", nargs="*", help="default: every registered method")
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--height", type=int, default=120)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--bounces", type=int, default=8)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--reuse-references", action="store_true",
                   help="keep OUT/reference and its noise from the last run (same --ref-spp)")
    args = p.parse_args()
    if not BUNNY.exists():
        sys.exit(f"specular_error: {BUNNY} is missing (bash scripts/fetch_data.sh)")
    methods = args.methods or [m["id"] for m in pcrt.methods()]
    (args.out / "reference").mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        refs = saved_references(args) if args.reuse_references else references(args, tmp)
        render(args, normals_scene(None), tmp / "n.mesh.exr", 1, 1, 0,
               ("--normals", str(tmp / "n.mesh.normals.exr"), "--depth",
                str(tmp / "n.mesh.depth.exr")))
        ref_n = rgb(tmp / "n.mesh.normals.exr")
        ref_z = pcrt.read_exr(str(tmp / "n.mesh.depth.exr"))["Z"]
        normals = {m: normal_error(args, tmp, m, ref_n, ref_z) for m in methods}
        rows, frames = [], {mat: [] for mat in MATERIALS}
        for mat in MATERIALS:
            for m in [None, *methods]:
                row, v = frame_row(args, tmp, mat, m, refs[mat]["image"], np.isfinite(ref_z))
                rows.append(row)
                frames[mat].append((v, row["method"]))
                print(f"{mat} {row['method']}: relMSE {row['relmse']:.4f}", flush=True)
    for mat in MATERIALS:
        sheet(args.out / f"sheet_{mat}.png", [refs[mat]["image"]] + [v for v, _ in frames[mat]],
              [f"reference S={args.ref_spp}"] + [l for _, l in frames[mat]])
    relation_plot(args.out / "error_vs_normal.png", rows, normals)
    settings = {k: v for k, v in vars(args).items() if k not in ("pcrt", "out", "methods")}
    (args.out / "metrics.json").write_text(json.dumps(
        {"settings": settings, "reference": {m: {k: v for k, v in r.items() if k != "image"}
                                             for m, r in refs.items()},
         "frames": rows, "normals": normals}, indent=1) + "\n")
    write_table(args, refs, rows, normals)
    print((args.out / "table.md").read_text())


if __name__ == "__main__":
    main()
