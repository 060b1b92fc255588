#!/usr/bin/env bash
# What a specular frame costs against a diffuse one, per method: the same scene (a point-cloud
# bunny on a mesh floor under a sphere light and a dim sampled sky) rendered with the bunny as
# smooth glass (eta 1.5), a mirror, a glossy conductor (GGX roughness 0.15, as in
# scripts/specular_error.py) and diffuse grey, alternated in one loop (glass, mirror, glossy,
# diffuse, glass, ...) so that a drift of the machine falls on every material alike, REPS each.
# Glass and mirror are delta lobes: their paths sample no light at the cloud and bounce on (glass
# through it); a glossy path samples the light like a diffuse one but bounces into a narrow lobe.
# The ratios of rays cast, items visited and render seconds to the diffuse frame are what a user
# pays for the material. One JSON per (method, material, rep) under
# OUT/material_cost, then scripts/material_cost.py writes OUT/material_cost.md and .json.
# Usage: scripts/material_cost.sh [build/bin/pcrt] [OUT=results/light_transport] [REPS=5]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/light_transport}
reps=${3:-5}
threads=${PCRT_THREADS:-2}
root=$(cd "$(dirname "$0")/.." && pwd)
materials="glass mirror glossy diffuse"
# PCRT_METHODS="id ..." reruns those methods only; the table is written from every JSON under OUT.
methods=${PCRT_METHODS:-$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')}
mkdir -p "$out/material_cost"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene() {  # scene METHOD MATERIAL -> a scene file on stdout
  local structure=""
  # The oracle's default is brute force (O(N) per ray); the kd-tree gives it the same hits.
  [ "$1" = reference_splat ] && structure='"structure": "kd_tree",'
  cat <<JSON
{"materials": {"glass": {"type": "dielectric", "eta": 1.5},
               "mirror": {"type": "mirror"},
               "glossy": {"type": "rough_conductor", "roughness": 0.15},
               "diffuse": {"type": "diffuse", "albedo": 0.75},
               "floor": {"type": "diffuse", "albedo": [0.7, 0.68, 0.62]}},
 "objects": [{"sample": "$root/data/bunny/bunny.off", "sampling": "n=20000,seed=1",
              "method": "$1", $structure "material": "$2",
              "transform": {"rotate": {"axis": [1, 0, 0], "degrees": 90}}},
             {"quad": {"size": 60}, "material": "floor"}],
 "lights": [{"type": "sphere", "position": [-8, -10, 22], "radius": 3, "radiance": 25},
            {"type": "environment", "radiance": [0.06, 0.07, 0.09]}],
 "camera": {"eye": [6, -26, 11], "target": [0, 0, 4], "fov": 34}}
JSON
}
for m in $methods; do
  for material in $materials; do scene "$m" "$material" >"$tmp/$m.$material.json"; done
  for r in $(seq 1 "$reps"); do
    for material in $materials; do
      "$pcrt" render --scene "$tmp/$m.$material.json" --out "$tmp/frame.exr" --width 160 \
        --height 120 --spp 4 --bounces 6 --threads "$threads" \
        --stats "$out/material_cost/$m.$material.$r.json" >/dev/null
    done
  done
done
python3 "$root/scripts/material_cost.py" "$out/material_cost" "$reps" "$out/material_cost.md"
echo "material cost: $out/material_cost.md, $out/material_cost.json"
