#!/usr/bin/env python3
"""Writes DIR/report.md from a sweep directory (runs.csv, fits.json, context.json): the verdicts
in the thesis's layout (one row per method or structure, claimed against measured), log-log plots
with the fitted line and the claimed slope (DIR/plots/*.png), the threshold claims, the
reconstruction crossover, and the accuracy table of the method issues (results/method_table.md).
Usage: scripts/report.py DIR   (Debian's python3 with python3-matplotlib and python3-numpy)"""
import csv
import hashlib
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

CLAIMED_SLOPE = {"1": 0.0, "log x": None, "x": 1.0, "x log x": None, "x^2": 2.0, "x^3": 3.0}


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def slug(text):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_")


def model_curve(model, x):
    return {"1": np.ones_like(x), "log x": np.log(x), "x": x, "x log x": x * np.log(x),
            "x^2": x ** 2, "x^3": x ** 3}[model]


def plot(fit, path):
    xs = np.array(fit["x_values"], dtype=float)
    ys = np.array(fit["y_values"], dtype=float)
    fig, ax = plt.subplots(figsize=(4.2, 3.2))
    ax.loglog(xs, ys, "o", ms=4, label="measured")
    grid = np.geomspace(xs.min(), xs.max(), 50)
    # The fitted log-log line through the geometric means.
    lx, ly = np.log(xs), np.log(ys)
    b = fit["exponent"]
    a = ly.mean() - b * lx.mean()
    ax.loglog(grid, np.exp(a) * grid ** b, "-", lw=1.2, label=f"fit: slope {b:.2f} [{fit['ci_low']:.2f}, {fit['ci_high']:.2f}]")
    # The claimed growth, scaled through the data's geometric mean.
    claimed = model_curve(fit["expected_model"], grid)
    if np.all(claimed > 0):
        at = model_curve(fit["expected_model"], xs)
        scale = math.exp(ly.mean() - np.log(at).mean()) if np.all(at > 0) else 1.0
        ax.loglog(grid, scale * claimed, "--", lw=1, label=f"claimed: {fit['expected_model']}")
    ax.set_xlabel(fit["x"])
    ax.set_ylabel(fit["metric"][:40], fontsize=7)
    ax.set_title(f"{fit['claim']} ({fit.get('dataset') or fit.get('workload', '')})", fontsize=8)
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def real_shape_sections(report_dir):
    """Accuracy on real meshes and the image comparison (issue 13), from the committed results of
    scripts/accuracy_meshes.sh and scripts/compare_sheet.sh, with the contact sheets linked."""
    results = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "results")
    out = []
    summary = os.path.join(results, "accuracy", "summary.md")
    if os.path.exists(summary):
        out.append("\n## Accuracy on real shapes (results/accuracy/summary.md)\n")
        out.append(open(summary).read())
    compare = os.path.join(results, "compare", "summary.md")
    if os.path.exists(compare):
        out.append("\n## Frames against the mesh (results/compare/summary.md)\n")
        out.append(open(compare).read())
        for shape in ("bunny", "cow"):
            sheet = os.path.join(results, "compare", f"{shape}_sheet.png")
            if os.path.exists(sheet):
                out.append(f"![{shape}: difference pictures]({os.path.relpath(sheet, report_dir)})\n")
    return out


def main():
    d = sys.argv[1]
    fits = json.load(open(os.path.join(d, "fits.json")))
    ctx = json.load(open(os.path.join(d, "context.json")))
    runs = list(csv.DictReader(open(os.path.join(d, "runs.csv"))))
    os.makedirs(os.path.join(d, "plots"), exist_ok=True)
    out = []
    cfg = ctx.get("config", {})
    out.append(f"# pcrt report: {cfg.get('name', os.path.basename(d))}\n")
    if cfg.get("description"):
        out.append(cfg["description"] + "\n")
    m = ctx.get("machine", {})
    out.append(f"Machine: {m.get('cpu', '?')}, {m.get('cores', '?')} cores, {m.get('memory', '?')}; "
               f"compiler {ctx.get('compiler', '?')} ({ctx.get('build_type', '?')}); commit "
               f"`{ctx.get('git_commit', '?')[:12]}`. Runs: {len(runs)}, of which "
               f"{sum(r['status'] != 'ok' for r in runs)} failed or timed out (listed at the end).\n")
    counts = {}
    for f in fits:
        counts[f["verdict"]] = counts.get(f["verdict"], 0) + 1
    out.append("Verdicts: " + ", ".join(f"{v} {n}" for v, n in sorted(counts.items())) + ".\n")
    out.append("A verdict compares the best model (AICc, with intercept, on relative errors) with the "
               "claimed one: *consistent* when the claimed model is within 2 AICc of the best, "
               "else *faster* or *slower* by order of growth. Operation counts are exact and machine "
               "independent; times are medians over the repetitions on this machine.\n")

    growth = [f for f in fits if "exponent" in f]
    subjects = sorted({f["method"] or f["structure"] or f["claim"].split("/")[0] for f in growth})
    out.append("## Claims in the thesis's layout\n")
    out.append("Plots are in `plots/` next to this file (`pcrt report DIR` draws them again).\n")
    out.append("| subject | claim | claimed | source | variable | metric | data | best model | exponent [95% CI] | R² | verdict | plot |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for s in subjects:
        for f in [f for f in growth if (f["method"] or f["structure"] or f["claim"].split("/")[0]) == s]:
            name = slug(f"{f['claim']}_{f['variable']}_{f['metric']}_{f.get('dataset') or f.get('workload')}_{hashlib.md5(json.dumps(f['group'], sort_keys=True).encode()).hexdigest()[:6]}")
            path = os.path.join("plots", name + ".png")
            plot(f, os.path.join(d, path))
            out.append(f"| {s} | {f['claim']} | {f.get('claimed', '')} | {f.get('source', '')} | {f['variable']} ({f['x']}) | "
                       f"{f['metric']} | {f.get('dataset') or f.get('workload', '')} | {f['best_model']} | "
                       f"{fmt(f['exponent'])} [{fmt(f['ci_low'])}, {fmt(f['ci_high'])}] | {fmt(f['r2'])} | "
                       f"**{f['verdict']}** | [png]({path}) |")
    thresholds = [f for f in fits if "threshold" in f]
    if thresholds:
        out.append("\n## Threshold claims\n")
        out.append("| claim | claimed | source | method | data | measured (worst run) | verdict |")
        out.append("|---|---|---|---|---|---|---|")
        for f in thresholds:
            out.append(f"| {f['claim']} | {f['threshold']} | {f.get('source', '')} | {f['method']} | {f['dataset']} | "
                       f"{fmt(f.get('measured'))} | **{f['verdict']}** |")
    cross = [r for r in runs if r["kind"] == "crossover" and r["status"] == "ok"]
    if cross:
        out.append("\n## Reconstruct-then-trace against direct tracing (chapter 7)\n")
        out.append("| method | data | N | M | direct setup (s) | direct frame (s) | afsr + engine setup (s) | mesh frame (s) | reconstruction pays off after |")
        out.append("|---|---|---|---|---|---|---|---|---|")
        for r in cross:
            f = r.get("crossover_frames", "")
            out.append(f"| {r['method']} | {r['dataset']} | {r['N']} | {r['M']} | {fmt(float(r['direct_setup_s']))} | "
                       f"{fmt(float(r['direct_frame_s']))} | {fmt(float(r['mesh_setup_s']))} | {fmt(float(r['mesh_frame_s']))} | "
                       f"{(f + ' frames') if f else 'never (direct frames are faster)'} |")
    errors = [f for f in fits if f["verdict"] == "error"]
    if errors:
        out.append("\n## Fits that could not be made\n")
        for f in errors:
            out.append(f"- {f['claim']} ({f.get('dataset', '')}): {f.get('error', '')}")
    table = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "results", "method_table.md")
    if os.path.exists(table):
        out.append("\n## Accuracy against exact surfaces (results/method_table.md)\n")
        out.append(open(table).read())
    out.extend(real_shape_sections(d))
    bad = [r for r in runs if r["status"] != "ok"]
    if bad:
        out.append("\n## Failed and timed-out runs (kept, not dropped)\n")
        for r in bad:
            out.append(f"- {r['experiment']} {r['method'] or r['reconstruction'] or r['workload']} {r['structure']} "
                       f"{r['dataset']} N={r['N']}: {r['status']}: {r['error']}")
    with open(os.path.join(d, "report.md"), "w") as fh:
        fh.write("\n".join(out) + "\n")
    print(f"{d}/report.md: {len(growth)} fits plotted, {len(thresholds)} threshold claims")


if __name__ == "__main__":
    main()
