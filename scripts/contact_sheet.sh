#!/usr/bin/env bash
# Renders every registered method on the bunny and on a real CGAL scan and lays the images side by
# side with their names: out/contact_sheet.png. Needs scripts/fetch_data.sh to have run.
set -euo pipefail
cd "$(dirname "$0")/.."
pcrt=${PCRT:-build/bin/pcrt}
mkdir -p out/contact
methods=$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')
scans=("data/bunny/bunny.ply:0.3,0.4,1:0,1,0" "data/cgal/points_3/kitten.xyz:0.55,-0.75,0.4:0,0,1")
for m in $methods; do
  structure=()
  [ "$m" = reference_splat ] && structure=(--structure kd_tree)
  for s in "${scans[@]}"; do
    IFS=: read -r file view up <<<"$s"
    name=$(basename "${file%.*}")
    "$pcrt" render --method "$m" "${structure[@]}" --data "$file" --out "out/contact/$m.$name.png" \
      --width 256 --height 256 --spp 4 --bounces 1 --view "$view" --up "$up" >/dev/null
  done
done
/usr/bin/python3 - out/contact out/contact_sheet.png $methods <<'PY'
import sys, matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt, matplotlib.image as im
folder, out, methods = sys.argv[1], sys.argv[2], sys.argv[3:]
scans = ["bunny", "kitten"]
fig, axes = plt.subplots(len(scans), len(methods), figsize=(2.6 * len(methods), 2.8 * len(scans)), squeeze=False)
for c, m in enumerate(methods):
    for r, s in enumerate(scans):
        ax = axes[r][c]
        ax.imshow(im.imread(f"{folder}/{m}.{s}.png"))
        ax.set_xticks([]); ax.set_yticks([])
        if r == 0: ax.set_title(m, fontsize=8)
        if c == 0: ax.set_ylabel(s)
plt.tight_layout()
plt.savefig(out, dpi=100)
print(out)
PY
