#!/usr/bin/env bash
# The white-furnace table of docs/light_transport.md: every registered method renders an object of
# albedo 1 under a uniform environment of radiance 1 through the renderer's own spawn rule
# (`pcrt furnace`), and the triangle mesh beside it as the floor of what geometry alone loses.
#   sphere, B=1: convex, so every dark pixel is a self-hit or a leak;
#   bunny (10^5 points sampled on the npm mesh), B=16: self-hits only cost a bounce there, so
#   what stays dark is light trapped inside the surface (a leak) or paths needing more bounces;
#   bunny_scan (noise 0.3 h, density falling by half, PCA normals), B=1 and B=16.
# Then the split of the dark pixels by cause, at S = 1 where it is exact (one path per pixel,
# through its centre; 256x256, B = 1): a camera ray whose own hit is false (the path started off
# the surface) or a path lost after a true camera-ray hit, against the exact surface (sphere,
# torus: the main job's demo shape; bunny: its mesh), with the exact surface itself (--exact) or
# the mesh as the floor row: what the shape loses with no method in between.
# One JSON per (case, method) under OUT; then scripts/furnace_table.py writes OUT/table.md.
# Usage: scripts/furnace_table.sh [build/bin/pcrt] [OUT=results/furnace]
# PCRT_METHODS="id ..." reruns those methods only (and the mesh and exact rows); the table is
# written from every JSON under OUT.
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/furnace}
threads=${PCRT_THREADS:-2}
methods=${PCRT_METHODS:-$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')}
frame=(--width 128 --height 128 --spp 4 --threads "$threads" --json)
bunny=data/bunny/bunny.off
# name|bounces|input
cases=(
  "sphere_b1|1|--data sphere:n=100000,seed=1"
  "bunny_b16|16|--truth $bunny --sample n=100000,seed=1"
  "bunny_scan_b1|1|--truth $bunny --sample n=100000,seed=1,noise=0.3,density=0.5,normals=estimated"
  "bunny_scan_b16|16|--truth $bunny --sample n=100000,seed=1,noise=0.3,density=0.5,normals=estimated"
)
for c in "${cases[@]}"; do
  IFS='|' read -r name bounces input <<<"$c"
  mkdir -p "$out/$name"
  for m in $methods; do
    structure=()
    # The oracle's default is brute force (O(N) per ray); the kd-tree gives it the same hits.
    [ "$m" = reference_splat ] && structure=(--structure kd_tree)
    # shellcheck disable=SC2086
    "$pcrt" furnace --method "$m" "${structure[@]}" $input --bounces "$bounces" "${frame[@]}" \
      >"$out/$name/$m.json"
  done
done
# The floor geometry sets: the bunny's own triangles (noise-free), at each bunny case's B.
for c in "bunny_b16|16" "bunny_scan_b1|1" "bunny_scan_b16|16"; do
  IFS='|' read -r name bounces <<<"$c"
  "$pcrt" furnace --mesh "$bunny" --engine embree --bounces "$bounces" "${frame[@]}" \
    >"$out/$name/mesh.json"
done
split=(--width 256 --height 256 --spp 1 --bounces 1 --threads "$threads" --json)
split_cases=(
  "split_sphere|--data sphere:n=100000,seed=1"
  "split_torus|--data torus:n=100000,seed=1"
  "split_bunny|--truth $bunny --sample n=100000,seed=1"
)
for c in "${split_cases[@]}"; do
  IFS='|' read -r name input <<<"$c"
  mkdir -p "$out/$name"
  for m in $methods; do
    structure=()
    [ "$m" = reference_splat ] && structure=(--structure kd_tree)
    # shellcheck disable=SC2086
    "$pcrt" furnace --method "$m" "${structure[@]}" $input "${split[@]}" >"$out/$name/$m.json"
  done
done
"$pcrt" furnace --exact --data sphere:n=100000,seed=1 "${split[@]}" >"$out/split_sphere/exact.json"
"$pcrt" furnace --exact --data torus:n=100000,seed=1 "${split[@]}" >"$out/split_torus/exact.json"
"$pcrt" furnace --mesh "$bunny" --engine embree "${split[@]}" >"$out/split_bunny/exact.json"
python3 scripts/furnace_table.py "$out" >"$out/table.md"
echo "furnace: $out/table.md"
