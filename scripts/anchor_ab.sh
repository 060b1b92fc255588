#!/usr/bin/env bash
# One structure's before and after in the same binary, on the anchor's three data sets: the
# "before" is the structure with the given parameters (an engineering switch turned off), run
# just before the "after" (the defaults, or AFTER's parameters). Usage:
# scripts/anchor_ab.sh OUT_DIR STRUCTURE "NAME=VALUE ..." [THREADS] ["NAME=VALUE ..." (AFTER)]
# Writes OUT_DIR/before/{sphere_1e6,building,b9_training}.json and OUT_DIR/*.json; compare with
# scripts/anchor_summary.py --ratios OUT_DIR/before/X.json OUT_DIR/X.json.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: anchor_ab.sh OUT_DIR STRUCTURE "NAME=VALUE ..." [THREADS]}
structure=${2:?structure}
before_sets=${3:?parameters of the before run}
threads=${4:-2}
after_sets=${5:-}
pcrt=${PCRT:-build/bin/pcrt}
# Runs a copy of the binary: the linker's output file of one build ran the octree's walks up to
# 0.39 slower than a byte-identical copy of it, cause not found (results/anchor/epyc_slab).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pcrt" "$tmp/pcrt"
pcrt=$tmp/pcrt
mkdir -p "$out/before"
sets=()
for s in $before_sets; do sets+=(--set "$s"); done
after=()
for s in $after_sets; do after+=(--set "$s"); done
run() {
  local dest=$1 data=$2
  shift 2
  "$pcrt" anchor --data "$data" --structure "$structure" --threads "$threads" --reps 7 --json \
    "$@" >"$dest.tmp"
  mv "$dest.tmp" "$dest"
}
for spec in sphere_1e6=sphere:n=1000000 building=data/cgal/points_3/building.ply \
  b9_training=data/cgal/points_3/b9_training.ply; do
  name=${spec%%=*}
  data=${spec#*=}
  run "$out/before/$name.json" "$data" "${sets[@]}"
  run "$out/$name.json" "$data" "${after[@]}"
  echo "$name done"
done
