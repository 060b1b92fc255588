#!/usr/bin/env bash
# The Gaussian particle methods (grt_2024, ever_2024: the methods whose paper structure is the bvh,
# whose leaf tests take one particle at a time) rendered on the bvh at several leaf sizes, the
# sizes alternated in each round: 256x256, one bounce, 2 threads, the building scan. Writes
# particles/METHOD_leaf_size=S_R.json (`pcrt render --stats`) and particles/context.json (the
# binary's build); table by particles.py.
# Usage: bash results/anchor/bvh_leaf/particles.sh [PCRT] [ROUNDS] (PCRT relative to the
# repository root; default build/bin/pcrt, 5 rounds)
set -euo pipefail
cd "$(dirname "$0")/../../.."
pcrt=${1:-build/bin/pcrt}
rounds=${2:-5}
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "particles.sh: ROUNDS '$rounds' is no positive integer" >&2; exit 1; }
[ -x "$pcrt" ] || { echo "particles.sh: no pcrt binary at $pcrt" >&2; exit 1; }
out=results/anchor/bvh_leaf/particles
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pcrt" "$tmp/pcrt"
# The binary's build commit (render --stats does not record it; the anchor's context does).
"$tmp/pcrt" anchor --data sphere:n=1000 --method reference_splat --structure bvh --width 8 \
  --height 8 --reps 1 --json | /usr/bin/python3 -c \
  'import json, sys; json.dump(json.load(sys.stdin)["context"], sys.stdout, indent=1)' \
  >"$out/context.json.tmp"
mv "$out/context.json.tmp" "$out/context.json"
for r in $(seq 1 "$rounds"); do
  for m in grt_2024 ever_2024; do
    for s in 0 8 16 32; do
      "$tmp/pcrt" render --method "$m" --data data/cgal/points_3/building.ply --width 256 \
        --height 256 --threads 2 --set "leaf_size=$s" --out "$tmp/frame.png" \
        --stats "$out/${m}_leaf_size=${s}_$r.json.tmp" >/dev/null
      mv "$out/${m}_leaf_size=${s}_$r.json.tmp" "$out/${m}_leaf_size=${s}_$r.json"
    done
  done
done
