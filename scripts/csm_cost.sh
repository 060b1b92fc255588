#!/usr/bin/env bash
# The cost of goradia_2011's caustic sample map (methods/goradia_2011/README.md, claims
# goradia_2011/csm_prepass and goradia_2011/csm_lookup): scenes/caustic_bunny.json with the number
# of photons P, the bunny's points N and the lookup's k swept, each a small frame whose own work
# does not depend on P (the map changes no ray of it), so that the prepass's ray-object work is the
# frame's work less that of the same frame at P = 0. The sweep harness fits only N, M, S, B, K, k
# and I on its generated datasets; P and the map's entries E are neither, so this script measures
# them and scripts/csm_cost.py fits them.
# Usage: scripts/csm_cost.sh [build/bin/pcrt] [OUT=results/caustics]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/caustics}
threads=${PCRT_THREADS:-2}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out/cost"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() {  # name N P k [csm_radius]
  python3 - "$here/scenes/caustic_bunny.json" "$here/data/bunny/bunny.off" "$2" "$3" "$4" "${5:-0.01}" \
    >"$tmp/$1.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
bunny = scene["objects"][0]
bunny["sample"] = sys.argv[2]
bunny["sampling"] = f"n={sys.argv[3]},seed=1"
bunny["set"] = {"csm_photons": int(sys.argv[4]), "csm_k": int(sys.argv[5]),
                "csm_radius": float(sys.argv[6])}
print(json.dumps(scene))
PY
  "$pcrt" render --scene "$tmp/$1.json" --out "$tmp/$1.png" --width 80 --height 60 --spp 1 \
    --bounces 8 --threads "$threads" --seed 1 --stats "$out/cost/$1.stats.json" >/dev/null
}
for n in 25000 50000 100000 200000 400000; do
  run "N${n}_P0" $n 0 64
  run "N${n}_P1000000" $n 1000000 64
done
for p in 250000 500000 2000000 4000000; do run "N100000_P$p" 100000 $p 64; done
# The lookup's claims without the radius bound (csm_radius = 1 diagonal): every lookup then
# gathers k entries, where the bound would gather all entries within it (as many as the density
# puts there, up to k) and hide both log E and k.
for p in 250000 500000 1000000 2000000 4000000; do run "N100000_P${p}_k64_r1" 100000 $p 64 1; done
for k in 8 16 32 128 256; do run "N100000_P1000000_k${k}_r1" 100000 1000000 $k 1; done
/usr/bin/python3 "$here/scripts/csm_cost.py" "$out/cost" "$out/csm_cost.md"
echo "csm cost: $out/csm_cost.md"
