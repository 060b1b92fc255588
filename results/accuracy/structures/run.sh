#!/usr/bin/env bash
# Does the structure change a blend method's frame? The splat family's blend methods blend the
# splats a ray hits within one leaf, so what a leaf holds is part of the method: the papers'
# octree (a splat in every cell it reaches), the loose octree (octree loose=1: each splat once,
# in the cell of its centre) and the bvh (each splat once, SAH leaves: by default of up to 16
# splats for these methods, two of their disc blocks; before f976a1a of up to 8, the bvh_leaf8
# variant). reference_splat (nearest disc, the same hits on any structure) is the control. The
# 8 shapes of scripts/accuracy_meshes.sh, 20 000 rays and 10 000 secondary rays each. Usage, from the repository root:
# bash results/accuracy/structures/run.sh [build/bin/pcrt]; then summary.py.
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=results/accuracy/structures
source scripts/accuracy_shapes.sh
# variant|structure|sets
variants=("octree|octree|" "octree_loose|octree|loose=1" "bvh|bvh|" "bvh_leaf8|bvh|leaf_size=8")
for s in "${accuracy_shapes[@]}"; do
  IFS='|' read -r name mesh sampling <<<"$s"
  for v in "${variants[@]}"; do
    IFS='|' read -r vname structure sets <<<"$v"
    mkdir -p "$out/$vname/$name"
    extra=()
    [ -n "$sets" ] && extra=(--set "$sets")
    for m in goradia_2010 kashyap_2010_splat linsen_2007 reference_splat; do
      "$pcrt" accuracy --method "$m" --structure "$structure" "${extra[@]}" --truth "$mesh" \
        --sample "$sampling" --rays 20000 --secondary 10000 --threads 2 --json \
        >"$out/$vname/$name/$m.json.tmp"
      mv "$out/$vname/$name/$m.json.tmp" "$out/$vname/$name/$m.json"
    done
  done
done
