#!/usr/bin/env bash
# The method table of docs/methods.md: accuracy on the exact sphere and torus (10^5 points, 20 000 rays,
# `pcrt accuracy`) and frames per second on a 10^6-point sphere at 512x512, 1 spp, 1 bounce,
# 2 threads (`pcrt render`), for every registered method on its default structure, and for the
# reconstruction baseline (advancing front, traced on our BVH) judged the same way.
# Usage: scripts/method_table.sh [build/bin/pcrt] > results/method_table.md
#        PCRT_METHODS="id ..." scripts/method_table.sh: those methods' rows only (no reconstruction),
#        for a method added since the table was made
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
all=$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')
methods=${PCRT_METHODS:-$all}
for m in $methods; do
  case " $all " in *" $m "*) ;; *) echo "method_table.sh: PCRT_METHODS: unknown method '$m'" >&2; exit 1 ;; esac
done
for m in $methods; do
  structure=()
  # The oracle's default is brute force (O(N) per ray); the kd-tree gives it the same hits.
  [ "$m" = reference_splat ] && structure=(--structure kd_tree)
  for d in sphere torus; do
    "$pcrt" accuracy --method "$m" "${structure[@]}" --data "$d:n=100000" --rays 20000 --threads 2 --json >"$tmp/$m.$d.json"
  done
  # A frame that takes longer than the limit (tejada_2006: brute-force secondary rays, O(N) each)
  # is reported as such, not left out.
  timeout "${PCRT_FRAME_LIMIT:-300}" "$pcrt" render --method "$m" "${structure[@]}" --data sphere:n=1000000 \
    --out "$tmp/$m.png" --width 512 --height 512 --spp 1 --bounces 1 --threads 2 \
    --stats "$tmp/$m.render.json" >/dev/null || echo "{\"timeout\": ${PCRT_FRAME_LIMIT:-300}}" >"$tmp/$m.render.json"
done
# The reconstruction side, point by point: the afsr mesh of the same clouds on our BVH.
if [ -z "${PCRT_METHODS:-}" ]; then
m=reconstruction:afsr
for d in sphere torus; do
  "$pcrt" accuracy --reconstruction afsr --engine bvh --data "$d:n=100000" --rays 20000 --threads 2 --json >"$tmp/$m.$d.json"
done
"$pcrt" reconstruct --method afsr --data sphere:n=1000000 --out "$tmp/afsr.ply" >/dev/null
"$pcrt" render --mesh "$tmp/afsr.ply" --engine bvh --out "$tmp/afsr.png" --width 512 --height 512 --spp 1 --bounces 1 \
  --threads 2 --stats "$tmp/$m.render.json" >/dev/null
methods="$methods $m"
fi
python3 - "$tmp" $methods <<'PY'
import json, sys
tmp, methods = sys.argv[1], sys.argv[2:]
print("| method | structure | data | holes | false hits | dist. median (h) | dist. p95 (h) | normal median (deg) | bounds | fps, 10^6 pts |")
print("|---|---|---|---|---|---|---|---|---|---|")
for m in methods:
    r = json.load(open(f"{tmp}/{m}.render.json"))
    fps = f"{1.0 / r['timings']['render']:.2f}" if "timings" in r else f"< {1.0 / r['timeout']:.4f} (no frame in {r['timeout']} s)"
    for d in ("sphere", "torus"):
        a = json.load(open(f"{tmp}/{m}.{d}.json"))
        f = lambda v, p=3: "n/a" if v is None else f"{v:.{p}f}"
        print(f"| {m} | {a['structure']} | {d} | {100*a['hole_rate']:.2f}% | {100*a['false_hit_rate']:.2f}% | "
              f"{f(a['distance_median_h'])} | {f(a['distance_p95_h'])} | {a['normal_median_deg']:.2g} | "
              f"{'met' if a['meets_bounds'] else 'MISSED'} | {fps} |")
PY
