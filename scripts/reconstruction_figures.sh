#!/usr/bin/env bash
# The figures docs/reconstruction.md quotes, each from its own command, into OUT: afsr of the
# 10^5-point sphere (time, triangles, boundary edges) and its mesh's accuracy, Delaunay of two
# skew lines of 1 000 points each, the triangle engines on the afsr mesh (pcrt_bench, one
# thread), and the frames after which reconstruct + trace beats goradia_2010's direct tracing.
# Run on a quiet machine from a clean build; each file records what made it.
# Usage: scripts/reconstruction_figures.sh [BUILD=build] [OUT=results/reconstruction]
set -euo pipefail
build=${1:-build}
out=${2:-results/reconstruction}
mkdir -p "$out"
pcrt=$build/bin/pcrt
git rev-parse --short HEAD >"$out/commit.txt"
git diff --quiet HEAD || echo "uncommitted changes" >>"$out/commit.txt"
"$pcrt" reconstruct --method afsr --data sphere:n=100000 --json >"$out/afsr_sphere.json"
"$pcrt" reconstruct --method delaunay --data skew_lines:n=2000 --json >"$out/delaunay_skew_lines.json"
"$pcrt" accuracy --reconstruction afsr --engine bvh --data sphere:n=100000 --rays 20000 --json \
  >"$out/afsr_sphere_accuracy.json"
"$build/bin/pcrt_bench" --benchmark_filter=MeshEngine --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true --benchmark_format=json >"$out/mesh_engines.json"
"$pcrt" crossover --data sphere:n=100000 --method goradia_2010 --width 256 --height 256 --json \
  >"$out/crossover_goradia_2010.json"
