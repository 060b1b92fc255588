#!/usr/bin/env bash
# reference_splat on the kd-tree and grid against Embree (pcrt anchor), three variants alternated
# three times: the binary before this change (item-order disc blocks copied, gathered from them:
# BEFORE), and this one with disc_blocks=0 (item order: gathered from the cloud's own arrays, no
# copy) and disc_blocks=1 (leaf-order blocks: a copy per reference).
# Usage: results/anchor/layouts/run.sh BEFORE_PCRT PCRT DATA_DIR OUT
set -euo pipefail
before=$1 pcrt=$2 data=$3 out=$4
for rep in 1 2 3; do
  for d in sphere building; do
    src="sphere:n=1000000"; [ $d = building ] && src="$data/cgal/points_3/building.ply"
    for s in kd_tree grid; do
      "$before" anchor --data "$src" --method reference_splat --structure $s --threads 2 --json >"$out/${d}_${s}_before_$rep.json"
      "$pcrt" anchor --data "$src" --method reference_splat --structure $s --threads 2 --set disc_blocks=0 --json >"$out/${d}_${s}_item_$rep.json"
      "$pcrt" anchor --data "$src" --method reference_splat --structure $s --threads 2 --set disc_blocks=1 --json >"$out/${d}_${s}_leaf_$rep.json"
      cat /proc/loadavg >>"$out/loadavg.txt"
    done
  done
done
