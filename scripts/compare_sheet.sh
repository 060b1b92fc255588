#!/usr/bin/env bash
# Image comparison of every method against the mesh (`pcrt compare`: same camera and light, B=0,
# through the renderer and each method's primary pass), on the bunny and the cow at 256x256 from
# 10^5 points sampled by area; one JSON and one difference PNG per (shape, method) under OUT, and
# a contact sheet OUT/<shape>_sheet.png of all difference pictures.
# Usage: scripts/compare_sheet.sh [build/bin/pcrt] [OUT=results/compare]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/compare}
threads=${PCRT_THREADS:-2}
methods=$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')
for s in "bunny|data/bunny/bunny.off" "cow|data/cgal/meshes/cow.off"; do
  IFS='|' read -r name mesh <<<"$s"
  mkdir -p "$out/$name"
  for m in $methods; do
    structure=()
    # Brute-force defaults trace their shadow rays on the kd-tree: the same hits, in seconds.
    [ "$m" = reference_splat ] && structure=(--structure kd_tree)
    [ "$m" = tejada_2006 ] && structure=(--structure kd_tree)
    "$pcrt" compare --method "$m" "${structure[@]}" --truth "$mesh" --sample n=100000 \
      --out "$out/$name/$m.png" --width 256 --height 256 --threads "$threads" --json >"$out/$name/$m.json"
  done
  /usr/bin/python3 scripts/contact_sheet_diff.py "$out/$name" "$out/${name}_sheet.png"
done
/usr/bin/python3 scripts/compare_table.py "$out" >"$out/summary.md"
