#!/usr/bin/env bash
# The main job: set up, fetch the real scans, render demo images with their statistics.
# (Later issues turn this into the default sweep with its report.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh build
bash scripts/fetch_data.sh
mkdir -p out
pcrt=build/bin/pcrt
# Until the acceleration structures land every ray tests every point (the O(N) oracle), so the
# demo clouds are kept small.
$pcrt render --method reference_splat --data torus:n=10000,seed=1 --out out/torus.png \
  --width 320 --height 320 --spp 2 --bounces 1 --stats out/torus.json --depth out/torus_depth.png
$pcrt render --method reference_splat --data data/bunny/bunny.ply --out out/bunny.png \
  --width 320 --height 320 --spp 2 --bounces 1 --stats out/bunny.json --normals out/bunny_normals.png \
  --view 0.3,0.4,1 --up 0,1,0
$pcrt info data/bunny/bunny.ply
echo "images and statistics in out/"
