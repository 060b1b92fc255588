#!/usr/bin/env bash
# The real-shape accuracy table of docs/accuracy.md: every registered method (and the afsr reconstruction)
# judged against CGAL demo meshes and the npm bunny by `pcrt accuracy --truth` (10^5 points
# sampled by area, 20 000 rays), plus one scanner-like variant (noise 0.3 h, density falling by
# half across the object, PCA normals), and 10 000 secondary rays leaving the true surface (half
# outward, half inward). One JSON per (shape, method) under OUT.
# Usage: scripts/accuracy_meshes.sh [build/bin/pcrt] [OUT=results/accuracy] [methods...]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/accuracy}
shift $(($# < 2 ? $# : 2))
threads=${PCRT_THREADS:-2}
methods=${*:-$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')}
source "$(dirname "$0")/accuracy_shapes.sh"
for s in "${accuracy_shapes[@]}"; do
  IFS='|' read -r name mesh sampling <<<"$s"
  mkdir -p "$out/$name"
  for m in $methods; do
    structure=()
    # The oracle's default is brute force (O(N) per ray); the kd-tree gives it the same hits.
    [ "$m" = reference_splat ] && structure=(--structure kd_tree)
    # tejada_2006 traces non-camera rays by brute force (O(N) each): its paper's own choice.
    [ "$m" = tejada_2006 ] && structure=(--structure kd_tree)
    "$pcrt" accuracy --method "$m" "${structure[@]}" --truth "$mesh" --sample "$sampling" \
      --rays 20000 --secondary 10000 --threads "$threads" --json >"$out/$name/$m.json"
  done
  "$pcrt" accuracy --reconstruction afsr --engine bvh --truth "$mesh" --sample "$sampling" \
    --rays 20000 --secondary 10000 --threads "$threads" --json >"$out/$name/reconstruction_afsr.json"
done
