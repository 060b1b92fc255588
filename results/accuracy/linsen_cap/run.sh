#!/usr/bin/env bash
# linsen_2007's splats before they were cut at the points they cover (issue 30): what set their
# radius on the elk, varied one cause at a time (the cap in cover radii, the normal field's
# neighbours, the error tolerance), and the phantoms on the elk, cow and bunny at the defaults.
# PCRT must be a build of 1b48764^, the commit before the cut (git worktree add DIR 1b48764^,
# then cmake and ninja there); the current code's figures are results/accuracy/{elk,cow,bunny}.
# Usage: results/accuracy/linsen_cap/run.sh PCRT [OUT=results/accuracy/linsen_cap]
set -euo pipefail
pcrt=$1
out=${2:-results/accuracy/linsen_cap}
mkdir -p "$out"
run() {  # run NAME MESH [--set ...]
  local name=$1 mesh=$2
  shift 2
  "$pcrt" accuracy --method linsen_2007 --truth "$mesh" --sample n=100000 --rays 20000 \
    --secondary 10000 --threads 2 --json "$@" >"$out/$name.json"
}
elk=data/cgal/meshes/elk.off
run elk_default "$elk"
for cap in 1 2 3; do run "elk_max_radius_scale_$cap" "$elk" --set max_radius_scale=$cap; done
for k in 32 64; do run "elk_field_k_$k" "$elk" --set field_k=$k; done
for tol in 0.02 0.05; do run "elk_error_tolerance_$tol" "$elk" --set error_tolerance=$tol; done
run cow_default data/cgal/meshes/cow.off
run bunny_default data/bunny/bunny.off
