#!/usr/bin/env bash
# The frame claims in B on paths that really bounce (configs/bounces.json: a closed mirror
# sphere, two facing mirrors, a glass sphere on a mesh floor), fitted and reported, and the table
# of docs/light_transport.md (bounce rays per camera ray, verdicts). About 4 minutes on 2 cores.
# Usage: scripts/bounces.sh [build/bin/pcrt] [OUT=results/bounces]
set -euo pipefail
pcrt=${1:-build/bin/pcrt}
out=${2:-results/bounces}
"$pcrt" sweep configs/bounces.json --out "$out" --overwrite
"$pcrt" fit "$out"
"$pcrt" report "$out"
python3 scripts/bounces_table.py "$out" >"$out/table.md"
echo "bounces: $out/report.md, $out/table.md"
