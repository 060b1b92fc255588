#!/usr/bin/env bash
# One parameter of one structure swept in the same binary on the anchor's three data sets, the
# values alternated within each round (each run's ratios are against Embree in its own process).
# Writes OUT/NAME=VALUE/{sphere_1e6,building,b9_training}_R.json; table by
# scripts/anchor_summary.py --rounds OUT/NAME=*/*.json (one row per value, data set and
# candidate). OUT and PCRT (the binary, default build/bin/pcrt) are relative to the repository
# root. Usage: scripts/anchor_sweep.sh OUT STRUCTURE NAME "VALUE ..." [ROUNDS] [THREADS] [ANCHOR ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: anchor_sweep.sh OUT STRUCTURE NAME \"VALUE ...\" [ROUNDS] [THREADS] [ANCHOR ARGS...]"
out=${1:?$usage}
structure=${2:?$usage}
name=${3:?$usage}
read -ra values <<<"${4:?$usage}"
rounds=${5:-3}
threads=${6:-2}
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "anchor_sweep.sh: ROUNDS '$rounds' is no positive integer" >&2; exit 1; }
[[ $threads =~ ^[0-9]+$ ]] || { echo "anchor_sweep.sh: THREADS '$threads' is no integer" >&2; exit 1; }
[ "${#values[@]}" -gt 0 ] || { echo "anchor_sweep.sh: no values to sweep" >&2; exit 1; }
shift $(($# < 6 ? $# : 6))
pcrt=${PCRT:-build/bin/pcrt}
[ -x "$pcrt" ] || { echo "anchor_sweep.sh: no pcrt binary at $pcrt" >&2; exit 1; }
# Runs a copy of the binary: the linker's output file of one build ran the octree's walks up to
# 0.39 slower than a byte-identical copy of it, cause not found (results/anchor/epyc_slab).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pcrt" "$tmp/pcrt"
for r in $(seq 1 "$rounds"); do
  for v in "${values[@]}"; do
    dir="$out/$name=$v"
    mkdir -p "$dir"
    for spec in sphere_1e6=sphere:n=1000000 building=data/cgal/points_3/building.ply \
      b9_training=data/cgal/points_3/b9_training.ply; do
      "$tmp/pcrt" anchor --data "${spec#*=}" --structure "$structure" --set "$name=$v" \
        --threads "$threads" --reps 7 --json "$@" >"$dir/${spec%%=*}_$r.json.tmp"
      mv "$dir/${spec%%=*}_$r.json.tmp" "$dir/${spec%%=*}_$r.json"
    done
  done
  echo "round $r done"
done
