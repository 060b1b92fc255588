#!/usr/bin/python3
"""A contact sheet of `pcrt compare` difference pictures: one tile per method with its missing,
extra and normal-off pixel rates from the JSON beside each PNG.

Usage: scripts/contact_sheet_diff.py DIR OUT.png
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main():
    directory, out = Path(sys.argv[1]), sys.argv[2]
    tiles = sorted(directory.glob("*.json"))
    if not tiles:
        sys.exit(f"contact_sheet_diff.py: no results in {directory}")
    cols = 6
    rows = (len(tiles) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(cols * 2.4, rows * 3.0))
    for ax in axes.flat:
        ax.axis("off")
    for ax, f in zip(axes.flat, tiles):
        j = json.loads(f.read_text())
        ax.imshow(mpimg.imread(f.with_suffix(".png")))
        ax.set_title(f"{j['method']}\nmiss {100 * j['missing_rate']:.1f}% extra "
                     f"{100 * j['extra_rate']:.1f}%\nnormal>30 {100 * j['normal_off_rate']:.1f}% "
                     f"RMSE {j['rmse']:.3f}", fontsize=7)
    fig.suptitle(f"{directory.name}: method vs mesh, red missing, blue extra, yellow normal "
                 f"> 30 deg, grey 4x radiance difference", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=90)


if __name__ == "__main__":
    main()
