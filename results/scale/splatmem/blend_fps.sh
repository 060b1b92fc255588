#!/usr/bin/env bash
# Frames per second of the splat-blending methods (and reference_splat on the kd-tree and bvh)
# with two binaries, passes alternated (order reversed every pass), on a 10^6-point sphere at
# 1024x1024, 1 spp, 1 bounce, 2 threads. One JSON line per run to OUT.jsonl; medians printed.
# Usage: blend_fps.sh OUT.jsonl OLD_PCRT NEW_PCRT [PASSES]
set -euo pipefail
out=$1 old=$2 new=$3 passes=${4:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
configs="goradia_2010 kashyap_2010_splat linsen_2007 reference_splat/kd_tree reference_splat/bvh goradia_2010/bvh"
for p in $(seq 1 "$passes"); do
  order="old new"; [ $((p % 2)) = 0 ] && order="new old"
  for c in $configs; do
    m=${c%%/*}; s=(); [[ $c == */* ]] && s=(--structure "${c#*/}")
    for which in $order; do
      bin=$old; [ "$which" = new ] && bin=$new
      "$bin" render --method "$m" "${s[@]}" --data sphere:n=1000000,seed=1 --out "$tmp/f.png" \
        --width 1024 --height 1024 --spp 1 --bounces 1 --threads 2 --stats "$tmp/s.json" >/dev/null
      /usr/bin/python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print(json.dumps({"config": sys.argv[2], "binary": sys.argv[3], "pass": int(sys.argv[4]), "frames_per_second": s["frames_per_second"], "counters": s["counters"]}))' \
        "$tmp/s.json" "$c" "$which" "$p" >>"$out"
    done
  done
done
/usr/bin/python3 - "$out" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print("| method/structure | old frames/s (median) | new frames/s (median) | new/old | passes | same counters |")
print("|---|---|---|---|---|---|")
for c in dict.fromkeys(r["config"] for r in rows):
    o = [r for r in rows if r["config"] == c and r["binary"] == "old"]
    n = [r for r in rows if r["config"] == c and r["binary"] == "new"]
    mo = statistics.median(r["frames_per_second"] for r in o)
    mn = statistics.median(r["frames_per_second"] for r in n)
    same = all(a["counters"] == b["counters"] for a in o for b in n)
    print(f"| {c} | {mo:.2f} | {mn:.2f} | {mn/mo:.2f} | {len(o)} | {'yes' if same else 'no'} |")
PY
