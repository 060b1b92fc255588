#!/usr/bin/env bash
# The caustic under a glass point-cloud bunny (methods/goradia_2011/README.md): scenes/
# caustic_bunny.json (goradia_2011: its caustic sample map) and scenes/caustic_bunny_kashyap.json
# (kashyap_2010_implicit: the same intersection, paths traced only) on the same rays, side by side
# in OUT/caustic_bunny.png with their difference (x4), and each frame's stats (time, counters).
# Usage: scripts/caustics.sh [build/bin/pcrt] [OUT=results/caustics]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/caustics}
threads=${PCRT_THREADS:-2}
spp=${SPP:-32}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in caustic_bunny caustic_bunny_kashyap; do
  "$pcrt" render --scene "$here/scenes/$s.json" --out "$tmp/$s.png" --width 400 --height 300 \
    --spp "$spp" --bounces 8 --threads "$threads" --seed 1 --stats "$out/$s.stats.json" >/dev/null
done
/usr/bin/python3 - "$tmp/caustic_bunny.png" "$tmp/caustic_bunny_kashyap.png" \
  "$out/caustic_bunny.png" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
left, right = (mpimg.imread(p)[..., :3] for p in sys.argv[1:3])
diff = np.clip(4 * np.abs(left - right), 0, 1)
gap = np.ones((left.shape[0], 6, 3), dtype=left.dtype)
mpimg.imsave(sys.argv[3], np.hstack([left, gap, right, gap, diff]))
PY
echo "caustics: $out/caustic_bunny.png (goradia_2011 | kashyap_2010_implicit | 4 x difference)"
