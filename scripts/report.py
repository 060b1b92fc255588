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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from verdicts import GROWTH, run_main, tally_text  # noqa: E402


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def slug(text):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_")


def model_curve(model, x):
    return {"1": np.ones_like(x), "log x": np.log(x), "x^0.5": np.sqrt(x), "x": x,
            "x log x": x * np.log(x), "x^2": x ** 2, "x^3": x ** 3}[model]


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


def num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return 0.0


def plot_name(f):
    key = hashlib.md5(json.dumps(f["group"], sort_keys=True).encode()).hexdigest()[:6]
    return slug(f"{f['claim']}_{f['variable']}_{f['metric']}_{f.get('dataset') or f.get('workload')}_{key}")


def growth_table(d, fits, plot_them):
    rows = ["| claim | about | claimed | source | variable | metric | data | best model | exponent [95% CI] | faster growth could carry (95%) | tight | verdict | why | plot |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for f in sorted(fits, key=lambda f: (f["claim"], f.get("dataset", ""), f["variable"], f["metric"])):
        path = os.path.join("plots", plot_name(f) + ".png")
        if plot_them:
            plot(f, os.path.join(d, path))
        bound = max((t["high95"] for t in f.get("faster_terms", []) if t["high95"] is not None), default=None)
        rows.append(f"| {f['claim']} | {f.get('about', '')} | {f.get('claimed', '')} | {f.get('source', '')} | {f['variable']} ({f['x']}) | "
                    f"{f['metric'][:60]} | {f.get('dataset') or f.get('workload', '')} | {f['best_model']} | "
                    f"{fmt(f['exponent'])} [{fmt(f['ci_low'])}, {fmt(f['ci_high'])}] | "
                    f"{'–' if bound is None else f'{100 * bound:.0f}%'} | {f.get('tightness', '')} | **{f['verdict']}** | {f.get('reason', '')} | [png]({path}) |")
    return "\n".join(rows)


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
               f"`{ctx.get('git_commit', '?')[:12]}`{' (with uncommitted changes)' if ctx.get('git_dirty') else ''}. Runs: {len(runs)}, of which "
               f"{sum(r['status'] != 'ok' for r in runs)} failed or timed out (listed at the end).\n")
    out.append(tally_text(fits) + "\n")
    out.append(
        "The thesis's O() are upper bounds on the worst case (Def. 5.1). A growth verdict on O(g) fits "
        "the claimed model a + b g (with a lower-order term where the replicates ask for one) against "
        "the same model plus a faster term c h: one class up, g x^0.25 between classes, and two classes "
        "up, and gives the share of y at the largest x that the faster term could carry. **holds**: "
        "every such share's 95% upper bound is under the tolerance (25%), the claimed model fits its "
        "replicates, x spans 2 decades in N and M (1 in K, k, S, B, I and H), no failed or missing run, "
        "and, with 6 or more distinct x, no single x changes the verdict; the column 'faster growth could carry' is how much a holds could be hiding. "
        "**exceeds**: a faster term's share is above 0 at 99% (with and without the lower-order term) "
        "and the exponent's CI lies above the claimed model's own. **inconclusive**: otherwise, naming "
        "the term it could not exclude. *tight*: the claimed class is needed on top of the class below. "
        "Threshold claims **meet** or **miss**; a missing measure is an **error**. Outside the tallies: "
        "**loop_check** (y/x constant, or its mean at each x within 10% over 30x of a linear claim, or "
        "a bound on I the cap keeps: the loops, not the claim), **drifted** (K as items per visited "
        "leaf, k, I or H moved by more than 20% while held), **not_judged** (the input "
        "misses the claim's precondition). Claims about pcrt's own scaffolding are tallied apart "
        "(about = pcrt). docs/verdicts.md has the rules and their measured power. Operation counts are "
        "exact and machine independent; times are medians over the repetitions on this machine.\n")
    judged = [f for f in fits if f["verdict"] in GROWTH]
    out.append("## Growth claims\n")
    out.append("Plots are in `plots/` next to this file (`pcrt report DIR` draws them again).\n")
    out.append(growth_table(d, judged, plot_them=True))
    idents = [f for f in fits if f["verdict"] == "loop_check"]
    if idents:
        out.append("\n## Loop checks (not tallied as confirmations)\n")
        out.append("The metric divided by x is the same at every x (or its mean at each x within 10% over "
                   "at least 30x of a linear claim): the loop does the same work per unit of x; or a "
                   "bound on I that the method's max_iterations keeps. This confirms the loop "
                   "structure; it cannot test the claim.\n")
        out.append("| claim | data | metric | x | y / x | reason |")
        out.append("|---|---|---|---|---|---|")
        for f in idents:
            # A bound on I met by construction is a threshold: no x, no y / x.
            r = fmt(f["y_values"][0] / f["x_values"][0], 7) if f.get("x_values") else "-"
            out.append(f"| {f['claim']} | {f['dataset']} | {f['metric']} | {f['x'] or '-'} | {r} | {f.get('reason', '')} |")
    drifted = [f for f in fits if f["verdict"] == "drifted"]
    if drifted:
        out.append("\n## Drifted groups (not judged)\n")
        out.append("A variable the experiment should hold fixed moved by more than 20% (one outlier left "
                   "out where a replicate at its x remains; K as items per visited leaf, k and H, and "
                   "I only for claims that name it; not a declared covariate, nor K, k where M, S "
                   "or B is swept), so the growth "
                   "cannot be attributed to the swept variable. The verdict the fit would have had is "
                   "shown for reference only.\n")
        out.append("| claim | data | variable | exponent [95% CI] | would be | why not judged |")
        out.append("|---|---|---|---|---|---|")
        for f in drifted:
            out.append(f"| {f['claim']} | {f['dataset']} | {f['variable']} | {fmt(f.get('exponent'))} "
                       f"[{fmt(f.get('ci_low'))}, {fmt(f.get('ci_high'))}] | {f.get('verdict_if_fixed', '')} | {f.get('reason', '')} |")
    thresholds = [f for f in fits if "threshold" in f]
    if thresholds:
        out.append("\n## Threshold claims\n")
        out.append("| claim | claimed | source | method | data | metric | measured (worst run) | verdict |")
        out.append("|---|---|---|---|---|---|---|---|")
        for f in thresholds:
            out.append(f"| {f['claim']} | {f['threshold']} | {f.get('source', '')} | {f['method']} | {f['dataset']} | "
                       f"{f['metric']} | {fmt(f.get('measured'))} | **{f['verdict']}** |")
    mls = [r for r in runs if r["status"] == "ok" and num(r.get("ops_mls_runs")) > 0 and r["experiment"] in ("mls_iterations", "tejada_2007_one_step")]
    if mls:
        out.append("\n## MLS runs by outcome (section 5.5.2)\n")
        out.append("Per hitting ray: every MLS fit the ray's leaves started (one k-NN query and one "
                   "plane + polynomial fit each). Per run: how each MLS iteration ended.\n")
        out.append("| method | data | fits per hitting ray | runs per hitting ray | converged | mean I of converged | capped | no root (ray misses the local polynomial) |")
        out.append("|---|---|---|---|---|---|---|---|")
        for r in mls:
            runs_n = num(r["ops_mls_runs"])
            hits = max(num(r.get("ops_ray_hits")), 1)
            conv = num(r.get("ops_mls_converged"))
            out.append(f"| {r['method']} | {r['dataset']} | {fmt(num(r['ops_mls_fits']) / hits)} | {fmt(runs_n / hits)} | "
                       f"{100 * conv / runs_n:.1f}% | {fmt(num(r.get('ops_mls_converged_iterations')) / conv if conv else None)} | "
                       f"{100 * num(r.get('ops_mls_capped')) / runs_n:.1f}% | {100 * num(r.get('ops_mls_no_root')) / runs_n:.1f}% |")
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
    unjudged = [f for f in fits if f["verdict"] in ("error", "not_judged")]
    if unjudged:
        out.append("\n## Fits that could not be made or do not apply (not judged)\n")
        for f in unjudged:
            out.append(f"- {f['claim']} ({f.get('dataset', '')}): {f['verdict']}: {f.get('error') or f.get('reason', '')}")
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
    print(f"{d}/report.md: {len(judged)} growth fits plotted; {tally_text(fits)}")


if __name__ == "__main__":
    sys.exit(run_main(main, "report.py DIR", 1))
