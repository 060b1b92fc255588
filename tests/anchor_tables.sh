#!/usr/bin/env bash
# The mesh-anchor tables quoted in results/anchor/*/summary.md are what scripts/anchor_summary.py
# --mesh makes from the JSON files committed beside them, and a file it cannot read is refused in
# one line with status 1. Usage: tests/anchor_tables.sh (from anywhere).
set -euo pipefail
cd "$(dirname "$0")/.."
summary=scripts/anchor_summary.py
for dir in results/anchor/tri_sah results/anchor/tri_prefetch; do
  table=$(/usr/bin/python3 "$summary" --mesh "$dir"/before/*.json "$dir"/after/*.json)
  while IFS= read -r line; do
    grep -qxF -- "$line" "$dir/summary.md" || {
      echo "anchor_tables: $dir/summary.md lacks the line: $line"
      exit 1
    }
  done <<<"$table"
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo '[1]' >"$tmp/list.json"
printf '{"context": {"build_commit": null' >"$tmp/truncated.json"
for bad in list truncated; do
  if /usr/bin/python3 "$summary" --mesh "$tmp/$bad.json" >"$tmp/out" 2>"$tmp/err"; then
    echo "anchor_tables: $bad.json was accepted"
    exit 1
  fi
  [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "$bad.json" "$tmp/err" || {
    echo "anchor_tables: $bad.json: not one line naming the file:"
    cat "$tmp/err"
    exit 1
  }
done
echo "anchor_tables: ok"
