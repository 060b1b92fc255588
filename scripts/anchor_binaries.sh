#!/usr/bin/env bash
# Two builds of pcrt on the anchor's three data sets, alternated: for each round, BEFORE_BIN then
# AFTER_BIN on the sphere, the building and the aerial tile, each an anchor run of its own against
# Embree (so each file's ratios are its own binary's against Embree in the same process). For a
# change no parameter can switch off (the walk's code itself); scripts/anchor_ab.sh compares
# parameter sets of one binary. Tables: scripts/anchor_summary.py --ratios OUT/before/X_R.json
# OUT/after/X_R.json, one per round R.
# Usage: scripts/anchor_binaries.sh OUT BEFORE_BIN AFTER_BIN [ROUNDS] [THREADS] [ANCHOR ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: anchor_binaries.sh OUT BEFORE_BIN AFTER_BIN [ROUNDS] [THREADS] [ANCHOR ARGS...]}
before=${2:?before binary}
after=${3:?after binary}
rounds=${4:-2}
threads=${5:-2}
shift $(($# < 5 ? $# : 5))
# Runs copies of the binaries: the linker's output file of one build ran the octree's walks up to
# 0.39 slower than a byte-identical copy of it, cause not found (results/anchor/epyc_slab).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$before" "$tmp/before"
cp "$after" "$tmp/after"
before=$tmp/before
after=$tmp/after
mkdir -p "$out/before" "$out/after"
for r in $(seq 1 "$rounds"); do
  for side in before after; do
    bin=$before
    [ "$side" = after ] && bin=$after
    for set in sphere_1e6:sphere:n=1000000 building:data/cgal/points_3/building.ply \
      b9_training:data/cgal/points_3/b9_training.ply; do
      name=${set%%:*}
      "$bin" anchor --data "${set#*:}" --threads "$threads" --reps 7 --json "$@" \
        >"$out/$side/${name}_$r.json.tmp"
      mv "$out/$side/${name}_$r.json.tmp" "$out/$side/${name}_$r.json"
    done
  done
done
