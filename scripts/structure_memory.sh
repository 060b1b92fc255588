#!/usr/bin/env bash
# The peak memory of structure builds alone (issue 16): build/bin/pcrt_structure_memory per
# structure and N (a generated sphere with reference_splat-like footprints; see
# structures/structure_memory.cpp), one JSON line per run appended to OUT/builds.jsonl with the
# commit it was built from and the process's peak resident memory (/usr/bin/time -v).
# Usage: scripts/structure_memory.sh OUT "N ..." "STRUCTURE ..." [BINARY [COMMIT]]
set -euo pipefail
out=$1
sizes=$2
structures=$3
bin=${4:-build/bin/pcrt_structure_memory}
commit=${5:-$(git rev-parse --short HEAD)}
mkdir -p "$out"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
for n in $sizes; do
  for s in $structures; do
    line=$(/usr/bin/time -v -o "$tmp" "$bin" "$s" "$n")
    rss_kb=$(sed -n 's/.*Maximum resident set size (kbytes): *//p' "$tmp")
    /usr/bin/python3 -c 'import json,sys; r=json.loads(sys.argv[1]); r["commit"]=sys.argv[2]; r["process_peak_bytes"]=int(sys.argv[3])*1024; print(json.dumps(r))' \
      "$line" "$commit" "$rss_kb" | tee -a "$out/builds.jsonl"
  done
done
