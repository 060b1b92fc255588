#!/usr/bin/env bash
# The anchor's three data sets (issue 31): the 10^6-point sphere, CGAL's building scan and its
# georeferenced aerial LIDAR tile, every splat-family method on every structure against Embree's
# discs ray by ray and in packets of 8 and 16. Usage: scripts/anchor_runs.sh OUT_DIR [THREADS]
# Writes OUT_DIR/{sphere_1e6,building,b9_training}.json and the load average around each run.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: anchor_runs.sh OUT_DIR [THREADS]}
threads=${2:-2}
pcrt=${PCRT:-build/bin/pcrt}
# Runs a copy of the binary: the linker's output file of one build ran the octree's walks up to
# 0.39 slower than a byte-identical copy of it, cause not found (results/anchor/epyc_slab).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pcrt" "$tmp/pcrt"
pcrt=$tmp/pcrt
mkdir -p "$out"
run() {
  local name=$1 data=$2
  "$pcrt" anchor --data "$data" --threads "$threads" --reps 7 --json >"$out/$name.json.tmp"
  mv "$out/$name.json.tmp" "$out/$name.json"
  echo "$name: $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['load_average'])" "$out/$name.json")"
}
run sphere_1e6 sphere:n=1000000
run building data/cgal/points_3/building.ply
run b9_training data/cgal/points_3/b9_training.ply
