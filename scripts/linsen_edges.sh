#!/usr/bin/env bash
# linsen_2007's splats at sharp edges (issue 30): `pcrt compare` of linsen_2007 and reference_splat
# against CGAL's fandisk and rotor (CAD parts, never used in development), 10^5 points, 256x256,
# one JSON and the frames per (shape, method) under OUT, then OUT/summary.md (false shadows: lit
# mesh pixels the method hits alike but leaves dark) and OUT/fandisk.png (the frames beside the
# mesh's, with OUT/before/fandisk.linsen_2007.method.png when present: the frame before the cut).
# Usage: scripts/linsen_edges.sh [build/bin/pcrt] [OUT=results/compare/linsen_edges]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/compare/linsen_edges}
mkdir -p "$out"
for shape in fandisk rotor; do
  for m in linsen_2007 reference_splat; do
    "$pcrt" compare --method "$m" --truth "data/cgal/meshes/$shape.off" --sample n=100000 \
      --out "$out/$shape.$m.diff.png" --images "$out/$shape.$m" --threads "${PCRT_THREADS:-2}" \
      --json >"$out/$shape.$m.json"
  done
done
/usr/bin/python3 - "$out" <<'PY'
import json, sys
from pathlib import Path
import matplotlib
matplotlib.use("Agg")
import matplotlib.image as mi
import matplotlib.pyplot as plt
out = Path(sys.argv[1])
rows = ["| shape | method | false shadows (of lit pixels) | extra pixels (of object) | "
        "normal > 30 deg | RMSE |", "|---|---|---|---|---|---|"]
for f in sorted(out.glob("*.json")):
    j = json.loads(f.read_text())
    shape = f.name.split(".")[0]
    rows.append(f"| {shape} | {j['method']} | {j['false_shadow']} of {j['lit_pixels']} "
                f"({100 * j['false_shadow_rate']:.2f}%) | {j['extra']} of {j['object_pixels']} | "
                f"{j['normal_off']} | {j['rmse']:.4f} |")
(out / "summary.md").write_text("\n".join(rows) + "\n")
panels = [(out / "before/fandisk.linsen_2007.method.png", "linsen_2007 before the cut"),
          (out / "fandisk.linsen_2007.method.png", "linsen_2007"),
          (out / "fandisk.reference_splat.method.png", "reference_splat"),
          (out / "fandisk.linsen_2007.truth.png", "mesh")]
panels = [(p, t) for p, t in panels if p.exists()]
fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 3.5))
for ax, (p, title) in zip(axes, panels):
    ax.imshow(mi.imread(p))
    ax.set_title(title, fontsize=9)
    ax.axis("off")
fig.tight_layout()
fig.savefig(out / "fandisk.png", dpi=80)
PY
echo "$out/summary.md, $out/fandisk.png"
