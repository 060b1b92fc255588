#!/usr/bin/env bash
# Wall time of a sweep in one process against 2 and 4 shards on a one-node Slurm cluster brought
# up by tests/slurm_cluster.sh (as root, slurm-wlm and munge installed), and the shard balance:
# the slowest shard's summed run time over the mean shard's, for pcrt's cost-balanced plan and
# for every n-th run (computed from the single sweep's run times).
# Usage: scripts/cluster_timing.sh [CONFIG] [CPUS_PER_TASK]   (default configs/quick.json, the
# config's threads)
set -euo pipefail
cd "$(dirname "$0")/.."
config=${1:-configs/quick.json}
cpus=${2:-}
pcrt=$PWD/build/bin/pcrt
source tests/slurm_cluster.sh
work=$(mktemp -d /tmp/pcrt_cluster_timing.XXXXXX)
chmod 0711 "$work"  # the cluster's munge socket lies below: every parent needs o+x
trap 'cluster_down; rm -rf "$work"' EXIT

now() { date +%s.%N; }
elapsed() { /usr/bin/python3 -c "import sys, time; print(time.time() - float(sys.argv[1]))" "$1"; }
wait_done() {
  local rc
  while :; do
    rc=0
    "$pcrt" cluster status "$1" >/dev/null || rc=$?
    [ $rc != 2 ] && return $rc
    sleep 0.5
  done
}
t0=$(now)
"$pcrt" sweep "$config" --out "$work/single" >/dev/null
single=$(elapsed "$t0")
cluster_up "$work/cluster"
printf '%-8s %10s %12s %16s %16s\n' shards "wall s" "to merged s" "balance (plan)" "balance (n-th)"
printf '%-8s %10.1f %12s %16s %16s\n' 1 "$single" - - -
for n in 2 4; do
  t0=$(now)
  "$pcrt" cluster submit "$config" --out "$work/s$n" --shards "$n" ${cpus:+--cpus-per-task "$cpus"} >/dev/null
  wait_done "$work/s$n" || { "$pcrt" cluster status "$work/s$n"; exit 1; }
  merged=$(elapsed "$t0")
  /usr/bin/python3 - "$work" "$n" "$merged" <<'PY'
import json, os, sys
work, n, merged = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
d = f"{work}/s{n}"
loads = []
first_start, last_end = None, 0.0
for i in range(n):
    runs = [json.loads(l) for l in open(f"{d}/shards/{i}/runs.jsonl")]
    loads.append(sum(r["wall_s"] for r in runs))
    end = os.path.getmtime(f"{d}/shards/{i}/runs.jsonl")
    start = os.path.getmtime(f"{d}/shards/{i}/context.json")
    first_start = start if first_start is None else min(first_start, start)
    last_end = max(last_end, end)
single = [json.loads(l) for l in open(f"{work}/single/runs.jsonl")]
# Every n-th run of the config's order (the order the single sweep ran them in).
nth = [0.0] * n
for k, r in enumerate(single):
    nth[k % n] += r["wall_s"]
bal = lambda xs: max(xs) / (sum(xs) / len(xs))
print(f"{n:<8} {last_end - first_start:10.1f} {merged:12.1f} {bal(loads):16.2f} {bal(nth):16.2f}")
PY
done
