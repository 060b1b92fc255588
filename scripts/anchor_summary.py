#!/usr/bin/env python3
"""Before/after tables of `pcrt anchor` JSON files (results/anchor/): per method and structure, the
median pass-by-pass ratio against Embree's discs in Morton order (and in cloud order) on primary,
bounce and shadow rays, and the disc tests per ray. Usage: anchor_summary.py BEFORE.json AFTER.json"""
import json
import sys


def rows(path):
    j = json.load(open(path))
    out = {}
    for c in j["candidates"]:
        out[(c["method"], c["structure"])] = c
    return j, out


def cell(c, k):
    if c is None:
        return "-"
    r = c[k]
    tests = r["work_per_ray"].get("splat_tests", 0)
    return "%.2f / %.2f (%.1f)" % (r["references"][0]["ratio"], r["references"][1]["ratio"], tests)


def main():
    bj, before = rows(sys.argv[1])
    aj, after = rows(sys.argv[2])
    print("%s, N = %d, %s lanes after; cells: ratio vs Embree Morton order / cloud order "
          "(disc tests per ray)\n" % (aj["dataset"], aj["N"], aj.get("leaf_simd", "?")))
    print("| method | structure | primary before | primary after | bounce before | bounce after "
          "| shadow before | shadow after |")
    print("|---|---|---|---|---|---|---|---|")
    for key in sorted(set(before) | set(after)):
        b, a = before.get(key), after.get(key)
        print("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
            key[0], key[1], cell(b, "primary"), cell(a, "primary"), cell(b, "bounce"),
            cell(a, "bounce"), cell(b, "shadow"), cell(a, "shadow")))
    for label, j in (("before", bj), ("after", aj)):
        for k in ("best", "best_same_discs"):
            b = j.get(k)
            if b:
                print("\n%s %s: %s on %s, primary x%.3f (Morton order)" % (
                    label, k, b["method"], b["structure"], b["primary"]["references"][0]["ratio"]))


main()
