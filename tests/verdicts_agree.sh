#!/usr/bin/env bash
# The committed thesis results say what docs/findings.md says, and the quick sweep (the main job)
# contradicts none of their verdicts on the same claim and data (inconclusive may meet a verdict).
set -euo pipefail
pcrt=$1
root=$(cd "$(dirname "$0")/.." && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
/usr/bin/python3 "$root/scripts/findings.py" "$root/results/thesis" --check "$root/docs/findings.md"
cd "$root"
"$pcrt" sweep configs/quick.json --out "$dir/quick" --fit >/dev/null
/usr/bin/python3 "$root/scripts/compare_verdicts.py" "$dir/quick" "$root/results/thesis"
