#!/usr/bin/env bash
# Frames per second of the projection-family methods, two binaries alternated run by run (A B A B
# ...), so that load from other jobs hits both alike: 512x512, 1 spp, 1 bounce, 2 threads (the
# method table's frame), `pcrt render --stats`, its timings.render. Each run's stats JSON and the
# load average before each pair are kept in OUT; scripts/projection_speed_summary.py tabulates.
# Usage: scripts/projection_speed.sh BEFORE_PCRT AFTER_PCRT OUT [PAIRS]
set -euo pipefail
before=$1 after=$2 out=$3 pairs=${4:-5}
mkdir -p "$out"
datasets=(sphere=sphere:n=1000000 building=data/cgal/points_3/building.ply)
configs=(schaufler_jensen_2000:octree schaufler_jensen_2000:bvh wand_strasser_2003:octree
         wand_strasser_2003:bvh goradia_2010:octree)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for ds in "${datasets[@]}"; do
  name=${ds%%=*} data=${ds#*=}
  for c in "${configs[@]}"; do
    m=${c%%:*} s=${c#*:}
    for ((p = 1; p <= pairs; ++p)); do
      echo "$name $m $s pair $p $(cat /proc/loadavg)" >>"$out/loadavg.txt"
      for side in before after; do
        bin=$before
        [ "$side" = after ] && bin=$after
        "$bin" render --method "$m" --structure "$s" --data "$data" --out "$tmp/x.png" \
          --width 512 --height 512 --spp 1 --bounces 1 --threads 2 \
          --stats "$out/$name.$m.$s.$side.$p.json" >/dev/null
      done
    done
  done
done
