#!/usr/bin/env bash
# How many splats linsen_2007's reduction keeps (counter splats_generated, `pcrt render --stats`)
# on generated and real clouds; writes results/scale/octree/linsen_kept.md.
# Usage: results/scale/octree/linsen_kept.sh PCRT DATA_DIR
set -euo pipefail
pcrt=$1 data=$2
out=$(dirname "$0")/linsen_kept.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
{
  echo "# linsen_2007: splats kept by the reduction (commit $(git rev-parse --short HEAD))"
  echo
  echo "| data | points | splats kept | fraction |"
  echo "|---|---|---|---|"
  for d in sphere:n=1000000,seed=1 bumpy_sphere:n=1000000,seed=1 torus:n=1000000,seed=1,noise=0.002 \
    "$data/cgal/points_3/building.ply" "$data/bunny/bunny.ply" "$data/cgal/points_3/kitten.xyz"; do
    "$pcrt" render --method linsen_2007 --data "$d" --threads 2 --out "$tmp/x.png" --stats "$tmp/s.json" >/dev/null
    /usr/bin/python3 - "$tmp/s.json" "${d#"$data"/}" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
n, kept = int(j["params"]["N"]), int(j["prepare_counters"]["splats_generated"])
print(f"| {sys.argv[2]} | {n} | {kept} | {100 * kept / n:.1f}% |")
PY
  done
} >"$out"
cat "$out"
