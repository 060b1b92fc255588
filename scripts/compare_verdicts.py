#!/usr/bin/env python3
"""Contradictions between two sweeps' verdicts on the same claim and data: one says the bound holds
where the other says it fails (exceeds), or meets against misses. Inconclusive, loop checks,
drifted, not judged and error contradict nothing. Time fits are left out (they depend on the machine).
Usage: scripts/compare_verdicts.py DIR_A DIR_B   (exit 1 on any contradiction)
       scripts/compare_verdicts.py --changes OLD_FITS_JSON NEW_FITS_JSON
                                      (every fit whose verdict moved, as a markdown table)"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from verdicts import run_main  # noqa: E402

SIDE = {"holds": "holds", "exceeds": "fails", "meets": "holds", "misses": "fails"}


def verdicts(d):
    out = {}
    for f in json.load(open(os.path.join(d, "fits.json"))):
        if "time" in f["metric"] or "fps" in f["metric"] or f["verdict"] not in SIDE:
            continue
        out.setdefault((f["claim"], f.get("dataset", ""), f["variable"]), []).append(f["verdict"])
    return out


def changes(old_path, new_path):
    key = lambda f: (f["claim"], os.path.basename(f.get("dataset") or ""), f.get("variable", ""), f["metric"])
    old = {key(f): f for f in json.load(open(old_path))}
    new = {key(f): f for f in json.load(open(new_path))}
    moved = {}
    for k in sorted(set(old) | set(new)):
        a = old.get(k, {}).get("verdict", "(absent)")
        b = new.get(k, {}).get("verdict", "(absent)")
        moved.setdefault((a, b), []).append(k)
    print("| was | now | fits |")
    print("|---|---|---|")
    for (a, b), ks in sorted(moved.items(), key=lambda m: -len(m[1])):
        print(f"| {a} | {b} | {len(ks)} |")
    print("\n| claim | data | variable | metric | was | now | why now |")
    print("|---|---|---|---|---|---|---|")
    for (a, b), ks in sorted(moved.items()):
        if a == b:
            continue
        for k in ks:
            why = (new.get(k) or {}).get("reason") or (new.get(k) or {}).get("error") or "not in the new config"
            print(f"| {k[0]} | {k[1]} | {k[2]} | {k[3][:50]} | {a} | {b} | {why.replace('|', '/')} |")
    return 0


def main():
    if sys.argv[1] == "--changes":
        if len(sys.argv) != 4:
            raise IndexError("--changes takes OLD_FITS_JSON NEW_FITS_JSON")
        return changes(sys.argv[2], sys.argv[3])
    a, b = verdicts(sys.argv[1]), verdicts(sys.argv[2])
    shared = sorted(set(a) & set(b))
    bad = [(k, a[k], b[k]) for k in shared
           if {SIDE[v] for v in a[k]} != {SIDE[v] for v in b[k]}]
    for k, va, vb in bad:
        print(f"contradiction: {k[0]} on {k[1]} in {k[2]}: {va} in {sys.argv[1]}, {vb} in {sys.argv[2]}")
    print(f"{len(shared)} claims judged in both, {len(bad)} contradictions")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(run_main(main, "compare_verdicts.py DIR_A DIR_B | --changes OLD_FITS_JSON NEW_FITS_JSON", 2))
