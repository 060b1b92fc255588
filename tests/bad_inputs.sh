#!/usr/bin/env bash
# The bad-input corpus (tests/bad_inputs/, plus large and special inputs generated here) against
#   replay BIN: pcrt_input_replay, every reader in process (scripts/test.sh runs it in an ASan +
#               UBSan build too), or
#   cli PCRT:   every command that reads each kind. Each run must exit 1 with exactly one line on
#               stderr naming the input, and leave an output file that was already there unchanged,
#               with no temporary beside it.
set -u
mode=$1 bin=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
gen="$dir/generated"
mkdir -p "$gen"
# Large or special inputs, made rather than committed.
/usr/bin/python3 -c "import sys; sys.stdout.write('[' * 1000000 + ']' * 1000000)" >"$gen/json_nested_1e6.json"
/usr/bin/python3 -c "import sys; sys.stdout.write('{\"a\":' * 50000 + '1' + '}' * 50000)" >"$gen/json_nested_5e4.json"
ln -s /dev/zero "$gen/dev_zero.xyz"
ln -s /dev/zero "$gen/dev_zero.ply"
ln -s /dev/urandom "$gen/dev_urandom.csv"
printf '0 0 0\nnan 1 1\n' >"$gen/name with
newline.xyz"
printf '0 0 0\nnan 1 1\n' >"$gen/name_with_$(printf '\033')escape.xyz"
mkdir "$gen/directory.ply" "$gen/directory.json"
corpus=("$here"/bad_inputs/* "$gen"/*)

if [ "$mode" = replay ]; then
  exec "$bin" "${corpus[@]}"
fi

pcrt=$bin
fails=0 runs=0
mkdir -p "$dir/sweep"
good_rays="$dir/good_rays.csv" good_mesh="$dir/good.off"
printf 'ox,oy,oz,dx,dy,dz\n0.2,0.2,5,0,0,-1\n' >"$good_rays"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$good_mesh"
# expect_rejected NAME OUTPUT pcrt-args...: exit 1, one stderr line containing NAME (printed as
# pcrt escapes it), OUTPUT (made beforehand) unchanged and no temporary beside it.
expect_rejected() {
  local name=$1 out=$2; shift 2
  runs=$((runs + 1))
  echo precious >"$out"
  timeout 60 "$pcrt" "$@" >"$dir/stdout" 2>"$dir/stderr"
  local rc=$? lines; lines=$(wc -l <"$dir/stderr")
  local shown; shown=$(/usr/bin/python3 -c '
import sys
s = sys.argv[1]
print("".join({"\n": "\\n", "\t": "\\t", "\r": "\\r", "\\": "\\\\"}.get(c) or (c if ord(c) >= 32 and ord(c) != 127 else "\\x%02x" % ord(c)) for c in s), end="")' "$name")
  local problem=""
  [ "$rc" -eq 1 ] || problem="exit $rc"
  [ "$lines" -eq 1 ] || problem="$problem; $lines stderr lines"
  grep -qF -- "$shown" "$dir/stderr" || problem="$problem; input not named"
  [ "$(cat "$out")" = precious ] || problem="$problem; $out changed"
  compgen -G "$out.tmp.*" >/dev/null && problem="$problem; a temporary was left"
  if [ -n "$problem" ]; then
    echo "FAIL ($problem): pcrt $*"; head -c 600 "$dir/stderr"; fails=$((fails + 1))
  else
    echo "ok: $(head -c 300 "$dir/stderr")"
  fi
}

# The harness's own files are read against a sweep of tests/fuzz/seeds/config/small.json: its
# plan of 3 shards (from --dry-run), and its finished folder, whose runs.jsonl each bad one replaces.
small="$here/fuzz/seeds/config/small.json"
"$pcrt" cluster submit "$small" --out "$dir/cluster" --shards 3 --dry-run >/dev/null
"$pcrt" sweep "$small" --out "$dir/done" >/dev/null
cp "$dir/done/runs.jsonl" "$dir/done.runs"
mkdir -p "$dir/merged"
for f in "${corpus[@]}"; do
  base=$(basename "$f")
  case "$base" in
    plan_*.json)
      expect_rejected "$f" "$dir/sweep/runs.jsonl" sweep "$small" --shard 0/3 --plan "$f" --out "$dir/sweep"
      ;;&
    jobs_*.json)
      cp "$f" "$dir/cluster/slurm/jobs.json"
      expect_rejected "$dir/cluster/slurm/jobs.json" "$dir/status.txt" cluster status "$dir/cluster"
      ;;&
    *.jsonl)
      cp "$f" "$dir/done/runs.jsonl"
      expect_rejected "$dir/done/runs.jsonl" "$dir/done/fits.json" fit "$dir/done"
      expect_rejected "$dir/done/runs.jsonl" "$dir/merged/keep.txt" merge "$dir/done" --out "$dir/merged"
      cp "$dir/done.runs" "$dir/done/runs.jsonl"
      ;;
    mesh_*.ply | mesh_*.off)
      for engine in bvh cgal_aabb embree; do
        expect_rejected "$f" "$dir/out.png" render --mesh "$f" --engine "$engine" --out "$dir/out.png" --width 8 --height 8
        expect_rejected "$f" "$dir/hits.csv" trace --mesh "$f" --engine "$engine" --rays "$good_rays" --out "$dir/hits.csv"
      done
      expect_rejected "$f" "$dir/diff.png" compare --method reference_splat --truth "$f" --out "$dir/diff.png" --width 8 --height 8
      expect_rejected "$f" "$dir/acc.txt" accuracy --method reference_splat --truth "$f" --rays 10
      ;;
    *.ply | *.xyz | *.pwn | *.off)
      expect_rejected "$f" "$dir/info.txt" info "$f"
      expect_rejected "$f" "$dir/out.png" render --method reference_splat --data "$f" --out "$dir/out.png" --width 8 --height 8
      expect_rejected "$f" "$dir/out.png" render --method embree_oriented_disc --data "$f" --out "$dir/out.png" --width 8 --height 8
      expect_rejected "$f" "$dir/out.ply" convert "$f" --out "$dir/out.ply"
      expect_rejected "$f" "$dir/mesh.ply" reconstruct --method delaunay --data "$f" --out "$dir/mesh.ply"
      case "$base" in *.off) ;; *)
        expect_rejected "$f" "$dir/out.png" render --stream --method hubo_2006 --set quantized=1 --data "$f" --out "$dir/out.png" --width 8 --height 8
      esac
      ;;
    *.csv)
      expect_rejected "$f" "$dir/hits.csv" trace --method reference_splat --data sphere:n=200 --rays "$f" --out "$dir/hits.csv"
      expect_rejected "$f" "$dir/hits.csv" trace --method embree_oriented_disc --data sphere:n=200 --rays "$f" --out "$dir/hits.csv"
      expect_rejected "$f" "$dir/hits.csv" trace --mesh "$good_mesh" --engine embree --rays "$f" --out "$dir/hits.csv"
      ;;
    *.json)
      expect_rejected "$f" "$dir/sweep/runs.jsonl" sweep "$f" --out "$dir/sweep"
      expect_rejected "$f" "$dir/check.txt" check --config "$f" --baseline "$root/results/baselines/ci.json"
      expect_rejected "$f" "$dir/check.txt" check --config "$root/configs/ci.json" --baseline "$f"
      ;;
    *.spec)
      spec=$(head -n 1 "$f")
      expect_rejected "$spec" "$dir/info.txt" info "$spec"
      expect_rejected "$spec" "$dir/out.png" render --method embree_oriented_disc --data "$spec" --out "$dir/out.png" --width 8 --height 8
      ;;
  esac
done
# The bound itself is accepted: a cloud spanning +-1e12 and rays from its corner run on Embree's
# discs, and its reconstruction on all three triangle engines.
/usr/bin/python3 -c "
import random
random.seed(1)
for _ in range(300): print(*(random.uniform(-1e12, 1e12) for _ in range(3)))" >"$dir/far.xyz"
printf 'ox,oy,oz,dx,dy,dz\n1e12,1e12,1e12,-1,-1,-1\n-1e12,0,0,1,0,0\n' >"$dir/far.csv"
accept() {  # accept pcrt-args...: must succeed
  runs=$((runs + 1))
  if ! "$pcrt" "$@" >/dev/null 2>"$dir/stderr"; then
    echo "FAIL (refused at the bound): pcrt $*"; cat "$dir/stderr"; fails=$((fails + 1))
  fi
}
accept render --method embree_oriented_disc --data "$dir/far.xyz" --out "$dir/far.png" --width 16 --height 16
accept trace --method embree_oriented_disc --data "$dir/far.xyz" --rays "$dir/far.csv" --out "$dir/far_hits.csv"
accept reconstruct --method afsr --data "$dir/far.xyz" --out "$dir/far_mesh.ply"
for engine in bvh cgal_aabb embree; do
  accept trace --mesh "$dir/far_mesh.ply" --engine "$engine" --rays "$dir/far.csv" --out "$dir/far_hits.csv"
done
echo "$runs runs over ${#corpus[@]} inputs: $fails failures"
[ "$fails" -eq 0 ]
