#!/usr/bin/python3
"""The image-comparison table from `scripts/compare_sheet.sh` output (DIR/<shape>/<method>.json):
per method and shape the missing, extra and normal-off (> 30 deg) pixels in % of the mesh's object
pixels, the missing pixels off the truth's silhouettes and occluding contours (interior), and the
false shadows (lit mesh pixels the method hits alike but leaves dark, in % of the lit pixels) and
the RMSE. Usage: scripts/compare_table.py [DIR=results/compare] > DIR/summary.md
"""
import json
import sys
from pathlib import Path

# Folders of DIR that hold a study of their own (scripts/linsen_edges.sh), not a shape.
STUDIES = {"linsen_edges"}
directory = Path(sys.argv[1] if len(sys.argv) > 1 else "results/compare")
rows = [json.loads(f.read_text()) | {"shape": f.parent.name}
        for f in sorted(directory.glob("*/*.json")) if f.parent.name not in STUDIES]
if not rows:
    sys.exit(f"compare_table.py: no results under {directory}")
shapes = sorted({r["shape"] for r in rows})


def interior(r):
    """Missing pixels more than edge_reach_px from the truth's silhouettes and contours, in %."""
    if "missing_at_edges" not in r:
        return "-"
    return f"{100 * (r['missing'] - r['missing_at_edges']) / r['object_pixels']:.2f}"


def false_shadows(r):
    """Lit mesh pixels the method hits with the same normal but leaves dark, in % of the lit."""
    return f"{100 * r['false_shadow_rate']:.2f}" if "false_shadow_rate" in r else "-"


edge_share = {r["shape"]: 100 * r["edge_pixels"] / r["object_pixels"] for r in rows if "edge_pixels" in r}
if edge_share:
    print("Interior: missing pixels more than 2 pixels from the mesh frame's silhouettes and occluding "
          "contours (a depth jump of more than 2%); those edges hold "
          + ", ".join(f"{v:.1f}% ({k})" for k, v in sorted(edge_share.items()))
          + " of the object pixels.\n")
print("| method | " + " | ".join(f"{s}: missing (interior) / extra / normal > 30 deg / false shadows / RMSE"
                                for s in shapes) + " |")
print("|---|" + "---|" * len(shapes))
for m in sorted({r["method"] for r in rows}):
    cells = []
    for s in shapes:
        r = next((r for r in rows if r["method"] == m and r["shape"] == s), None)
        cells.append("-" if r is None else
                     f"{100 * r['missing_rate']:.2f} ({interior(r)}) / {100 * r['extra_rate']:.2f} / "
                     f"{100 * r['normal_off_rate']:.2f} / {false_shadows(r)} / {r['rmse']:.4f}")
    print(f"| {m} | " + " | ".join(cells) + " |")
