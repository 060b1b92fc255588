#!/usr/bin/env python3
"""The table of docs/light_transport.md for a bounces sweep (configs/bounces.json): per scene and
method, bounce rays per camera ray at three B (the mean over replicates; B when every path bounces
B times) and the verdict of the frame claim in B with its reason's start. Missing runs, failed
runs or a missing fit are an error naming the file, never a blank cell."""
import json
import pathlib
import sys

SHOWN_B = [1, 8, 32]


def load_lines(path):
    try:
        return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    except (OSError, ValueError) as e:
        sys.exit(f"bounces_table: {path}: {e}")


def load_fits(path):
    try:
        d = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"bounces_table: {path}: {e}")
    return d["fits"] if isinstance(d, dict) else d


def bounces_per_path(runs, experiment, method, b, path):
    rows = [r for r in runs if r["experiment"] == experiment and r.get("method") == method
            and r.get("B") == b]
    if not rows or any(r["status"] != "ok" for r in rows):
        sys.exit(f"bounces_table: {path}: {experiment}/{method} at B = {b}: missing or failed")
    return sum(r["counters"].get("bounce_rays", 0) / r["counters"]["primary_rays"]
               for r in rows) / len(rows)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: bounces_table.py RESULTS_DIR")
    out = pathlib.Path(sys.argv[1])
    runs = load_lines(out / "runs.jsonl")
    fits = load_fits(out / "fits.json")
    experiments = sorted({f["experiment"] for f in fits}, key=lambda e: [f["experiment"]
                                                                      for f in fits].index(e))
    for e in experiments:
        print(f"\n{e}: bounce rays per camera ray at B = {', '.join(map(str, SHOWN_B))}; "
              "the frame claim in B\n")
        print("| method | " + " | ".join(f"B = {b}" for b in SHOWN_B) + " | verdict | why |")
        print("|---|" + "---|" * (len(SHOWN_B) + 2))
        for f in sorted((f for f in fits if f["experiment"] == e), key=lambda f: f["method"]):
            cells = [f"{bounces_per_path(runs, e, f['method'], b, out / 'runs.jsonl'):.2f}"
                     for b in SHOWN_B]
            reason = (f.get("reason") or "").split(" (95%")[0].split(", with or")[0]
            print(f"| {f['method']} | " + " | ".join(cells) + f" | {f['verdict']} | {reason} |")


if __name__ == "__main__":
    main()
