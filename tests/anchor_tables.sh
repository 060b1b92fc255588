#!/usr/bin/env bash
# The anchor tables quoted in results/anchor/*/summary.md are what scripts/anchor_summary.py makes
# from the JSON files committed beside them (--mesh for the triangle runs, --table against each of
# the three references for the whole anchor, --rounds for alternated binaries), and a file it
# cannot read is refused in one line with status 1. Usage: tests/anchor_tables.sh (from anywhere).
set -euo pipefail
cd "$(dirname "$0")/.."
summary=scripts/anchor_summary.py
# Every line of `table` is a line of summary.md in `dir`.
quoted() {
  local dir=$1 table=$2
  while IFS= read -r line; do
    grep -qxF -- "$line" "$dir/summary.md" || {
      echo "anchor_tables: $dir/summary.md lacks the line: $line"
      exit 1
    }
  done <<<"$table"
}
for dir in results/anchor/tri_sah results/anchor/tri_prefetch results/anchor/tri_planes; do
  quoted "$dir" "$(/usr/bin/python3 "$summary" --mesh "$dir"/before/*.json "$dir"/after/*.json)"
done
for dir in results/anchor/epyc_slab results/anchor/epyc_sort results/anchor/oct_flat; do
  files=("$dir"/sphere_1e6.json "$dir"/building.json "$dir"/b9_training.json)
  quoted "$dir" "$(/usr/bin/python3 "$summary" --table "${files[@]}")"
  for ref in 2 3; do
    quoted "$dir" "$(/usr/bin/python3 "$summary" --table --reference "$ref" "${files[@]}" | grep '^|')"
  done
done
for run in results/anchor/oct_flat/before results/anchor/oct_flat/r2; do
  quoted results/anchor/oct_flat "$(/usr/bin/python3 "$summary" --table "$run"/sphere_1e6.json \
    "$run"/building.json "$run"/b9_training.json | grep '| octree |')"
done
quoted results/anchor/oct_flat "$(/usr/bin/python3 "$summary" --rounds \
  results/anchor/oct_flat/ab/before/*.json results/anchor/oct_flat/ab/after/*.json)"
leaf=results/anchor/bvh_leaf
quoted "$leaf" "$(/usr/bin/python3 "$summary" --rounds --reference 3 "$leaf"/leaf_size=*/*.json)"
for ref in 0 3; do
  quoted "$leaf" "$(/usr/bin/python3 "$summary" --rounds --reference "$ref" \
    "$leaf"/ab/before/*.json "$leaf"/ab/after/*.json)"
done
quoted "$leaf" "$(/usr/bin/python3 "$leaf"/particles.py)"
blend=results/anchor/blend_t
quoted "$blend" "$(/usr/bin/python3 "$summary" --rounds "$blend"/octree/{before,after}/*.json)"
quoted "$blend" "$(/usr/bin/python3 "$summary" --rounds --reference 3 \
  "$blend"/bvh/{before,after}/*.json)"
quoted results/anchor/issue31 "$(/usr/bin/python3 results/anchor/issue31/table.py)"
quoted results/anchor/shadow16 "$(/usr/bin/python3 results/anchor/shadow16/table.py)"
quoted results/anchor/octree_recheck "$(/usr/bin/python3 "$summary" --rounds \
  results/anchor/octree_recheck/*/*.json | grep -E '^\| [0-9a-f]{7} .*(goradia|kashyap|linsen)')"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# issue31/table.py: a run it cannot read, or a side with no runs, is refused in one line.
i31=$tmp/issue31
for bad in '[1]' '{"candidates": [{"method": "m"}]' '{"dataset": "d", "candidates": 1}' \
  '{"context": {"build_commit": null, "build_dirty": false}, "load_average": {}}'; do
  cp -r results/anchor/issue31 "$i31"
  printf '%s' "$bad" >"$i31/after/building_2.json"
  if /usr/bin/python3 "$i31"/table.py "$i31" >"$tmp/out" 2>"$tmp/err"; then
    echo "anchor_tables: issue31/table.py accepted after/building_2.json: $bad"
    exit 1
  fi
  [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q building_2.json "$tmp/err" || {
    echo "anchor_tables: issue31/table.py, $bad: not one line naming the file:"
    cat "$tmp/err"
    exit 1
  }
  rm -rf "$i31"
done
# A side without its mesh runs, a round missing on one side: refused in one line.
for missing in 'mesh_c733_*.json' 'after/building_3.json' 'mesh_a9_2.json'; do
  cp -r results/anchor/issue31 "$i31"
  (cd "$i31" && rm $missing)
  if /usr/bin/python3 "$i31"/table.py "$i31" >"$tmp/out" 2>"$tmp/err" ||
    [ "$(wc -l <"$tmp/err")" -ne 1 ]; then
    echo "anchor_tables: issue31/table.py without $missing: not one line and status 1"
    exit 1
  fi
  rm -rf "$i31"
done
echo '[1]' >"$tmp/list.json"
printf '{"context": {"build_commit": null' >"$tmp/truncated.json"
printf '{"context": {"build_commit": "0", "build_dirty": false}, "dataset": "d", %s}\n' \
  '"candidates": [{"method": "m", "structure": "s"}]' >"$tmp/bare.json"
for mode in --mesh --rounds; do
  for bad in list truncated bare; do
    if /usr/bin/python3 "$summary" "$mode" "$tmp/$bad.json" >"$tmp/out" 2>"$tmp/err"; then
      echo "anchor_tables: $mode $bad.json was accepted"
      exit 1
    fi
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "$bad.json" "$tmp/err" || {
      echo "anchor_tables: $mode $bad.json: not one line naming the file:"
      cat "$tmp/err"
      exit 1
    }
  done
done
# particles.py: a run or context file it cannot read is refused in one line naming it.
pdir=$tmp/particles
mkdir -p "$pdir"
cp results/anchor/bvh_leaf/particles/context.json "$pdir/"
run=grt_2024_leaf_size=8_1.json
for bad in '[1]' '{"timings": {"render": 1}, "counters": [1]}' '{"timings"' \
  '{"timings": {"render": 1}, "counters": {"rays_cast": 0}}'; do
  printf '%s' "$bad" >"$pdir/$run"
  for file in "$run" context.json; do
    [ "$file" = context.json ] && printf '%s' "$bad" >"$pdir/context.json"
    if /usr/bin/python3 "$leaf"/particles.py "$pdir" >"$tmp/out" 2>"$tmp/err"; then
      echo "anchor_tables: particles.py accepted $file: $bad"
      exit 1
    fi
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "$file" "$tmp/err" || {
      echo "anchor_tables: particles.py, $file $bad: not one line naming the file:"
      cat "$tmp/err"
      exit 1
    }
  done
  cp results/anchor/bvh_leaf/particles/context.json "$pdir/"
done
echo "anchor_tables: ok"
