#!/usr/bin/env bash
# Frames per second of two binaries, /tmp/pcrt_before and /tmp/pcrt_after, alternated, 3 rounds,
# 2 threads, 512x512, 1 spp, 1 bounce; one stats file per frame in OUT. Usage: frames.sh OUT
set -euo pipefail
out=$(realpath -m "${1:?usage: frames.sh OUT}")
mkdir -p "$out"
cd "$(dirname "$0")/../../.."
for r in 1 2 3; do
  for side in before after; do
    for spec in "reference_splat:kd_tree:sphere:n=1000000" "goradia_2010:octree:data/cgal/points_3/building.ply" "reference_splat:bvh:data/cgal/points_3/b9_training.ply"; do
      m=${spec%%:*}; rest=${spec#*:}; s=${rest%%:*}; data=${rest#*:}
      name=$(basename "${data%%:*}" .ply)
      /tmp/pcrt_$side render --method "$m" --structure "$s" --data "$data" --threads 2 \
        --out /tmp/fps_frame.png --stats "$out/${side}_${m}_${s}_${name}_$r.json" >/dev/null
    done
  done
done
