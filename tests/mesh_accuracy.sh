#!/usr/bin/env bash
# The mesh-truth accuracy gate: every method on CGAL's elk (3x10^4 points sampled by area, exact
# normals, 10^4 rays, fixed seeds) against the figures recorded in RECORD. Fails when a method's
# see-through, phantom or hole count rises above its record (by more than 2 rays, for rounding
# across compilers) or a method has no record. Exit 77 (skipped) when data/ is not fetched.
# Usage: tests/mesh_accuracy.sh PCRT DATA_DIR RECORD [--update]
set -euo pipefail
pcrt=$1
mesh=$2/cgal/meshes/elk.off
record=$3
update=${4:-}
if [ ! -f "$mesh" ]; then
  echo "mesh_accuracy: $mesh not fetched (scripts/fetch_data.sh): skipped"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
methods=$("$pcrt" list --json | python3 -c 'import json,sys; print(" ".join(m["id"] for m in json.load(sys.stdin)["methods"]))')
for m in $methods; do
  structure=()
  # brute_force defaults (O(N) per ray) traced on the kd-tree: the same hits, in seconds.
  [ "$m" = reference_splat ] && structure=(--structure kd_tree)
  [ "$m" = tejada_2006 ] && structure=(--structure kd_tree)
  "$pcrt" accuracy --method "$m" "${structure[@]}" --truth "$mesh" --sample n=30000,seed=1 \
    --rays 10000 --seed 1 --threads 2 --json >"$dir/$m.json"
done
python3 - "$dir" "$record" "$update" <<'PY'
import json, sys
from pathlib import Path
out, record, update = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3] == "--update"
keys = ["see_through", "phantom", "holes"]
now = {}
for f in sorted(out.glob("*.json")):
    j = json.loads(f.read_text())
    now[j["method"]] = {k: j[k] for k in keys + ["judged_hits", "judged_misses"]}
if update:
    record.write_text(json.dumps({"mesh": "cgal/meshes/elk.off", "sample": "n=30000,seed=1",
                                  "rays": 10000, "methods": now}, indent=1, sort_keys=True) + "\n")
    print(f"{record}: {len(now)} methods recorded")
    sys.exit(0)
rec = json.loads(record.read_text())["methods"]
failures = []
for m, v in now.items():
    if m not in rec:
        failures.append(f"{m}: no recorded figures in {record} (run with --update)")
        continue
    for k in keys:
        if v[k] > rec[m][k] + 2:
            failures.append(f"{m}: {k} {v[k]} rays > recorded {rec[m][k]} "
                            f"({100 * v[k] / max(v['judged_hits'], 1):.2f}% of judged hits)")
for f in failures:
    print("FAIL", f)
print(f"mesh_accuracy: {len(now)} methods, {len(failures)} regressions")
sys.exit(1 if failures else 0)
PY
