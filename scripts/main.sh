#!/usr/bin/env bash
# The main job: set up, fetch the real scans, run the default sweep (configs/quick.json) with its
# fits and report, and render a few demo images with their statistics.
# Results: results/quick/{runs.jsonl,runs.csv,context.json,fits.json,fits.csv,report.md,plots/}
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh build
bash scripts/fetch_data.sh
pcrt=build/bin/pcrt
$pcrt sweep configs/quick.json --out results/quick --overwrite
$pcrt fit results/quick
$pcrt report results/quick
mkdir -p out
$pcrt render --method goradia_2010 --data bumpy_sphere:n=1000000,seed=1 \
  --out out/bumpy_sphere.png --width 512 --height 512 --spp 2 --bounces 1 --stats out/bumpy_sphere.json \
  --depth out/bumpy_sphere_depth.png
$pcrt render --method hubo_2006 --data torus:n=100000,seed=1 --out out/torus.png \
  --width 512 --height 512 --spp 2 --bounces 1 --stats out/torus.json --normals out/torus_normals.png
$pcrt render --method adamson_alexa_2003 --data data/bunny/bunny.ply --out out/bunny.png \
  --width 512 --height 512 --spp 2 --bounces 1 --stats out/bunny.json --view 0.3,0.4,1 --up 0,1,0
echo "report: results/quick/report.md; images and statistics in out/"
