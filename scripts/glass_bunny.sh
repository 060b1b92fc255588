#!/usr/bin/env bash
# The glass bunny of docs/light_transport.md: scenes/glass_bunny.json (10^5 points sampled on the
# npm bunny, reference_splat on its kd-tree) and scenes/glass_bunny_mesh.json (the mesh on
# Embree), both smooth glass on a mesh floor under a sphere light, side by side in
# OUT/glass_bunny.png with each frame's stats beside it.
# Usage: scripts/glass_bunny.sh [build/bin/pcrt] [OUT=results/light_transport]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/light_transport}
threads=${PCRT_THREADS:-2}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in glass_bunny glass_bunny_mesh; do
  "$pcrt" render --scene "$here/scenes/$s.json" --out "$tmp/$s.png" --width 400 --height 300 \
    --spp 64 --bounces 8 --threads "$threads" --stats "$out/$s.stats.json" >/dev/null
done
/usr/bin/python3 - "$tmp/glass_bunny.png" "$tmp/glass_bunny_mesh.png" "$out/glass_bunny.png" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
left, right = (mpimg.imread(p)[..., :3] for p in sys.argv[1:3])
gap = np.ones((left.shape[0], 6, 3), dtype=left.dtype)
mpimg.imsave(sys.argv[3], np.hstack([left, gap, right]))
PY
echo "glass bunny: $out/glass_bunny.png"
