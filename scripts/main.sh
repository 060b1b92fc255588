#!/usr/bin/env bash
# The main job: set up, fetch the real scans, render demo images with their statistics.
# (Later issues turn this into the default sweep with its report.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh build
bash scripts/fetch_data.sh
mkdir -p out
pcrt=build/bin/pcrt
$pcrt render --method reference_splat --structure kd_tree --data bumpy_sphere:n=1000000,seed=1 \
  --out out/bumpy_sphere.png --width 512 --height 512 --spp 2 --bounces 1 --stats out/bumpy_sphere.json \
  --depth out/bumpy_sphere_depth.png
$pcrt render --method reference_splat --structure octree --data torus:n=100000,seed=1 --out out/torus.png \
  --width 512 --height 512 --spp 2 --bounces 1 --stats out/torus.json --normals out/torus_normals.png
$pcrt render --method reference_splat --structure sphere_tree --data data/bunny/bunny.ply --out out/bunny.png \
  --width 512 --height 512 --spp 2 --bounces 1 --stats out/bunny.json --view 0.3,0.4,1 --up 0,1,0
$pcrt info data/bunny/bunny.ply
echo "images and statistics in out/"
