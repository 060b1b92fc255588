#!/usr/bin/env bash
# pcrt calibrate on a loaded machine: RUNS calibrations while LOAD busy loops compete for the
# cores, each run's wrong classifications listed. The first run waits until the 1-minute load
# average has risen to three quarters of LOAD (at most 3 minutes): it lags the loops, and the
# table records it per run. LOAD=0 calibrates on the machine as it is. Usage:
#   scripts/calibrate_loaded.sh PCRT OUT.md [RUNS=8] [LOAD=4]
set -euo pipefail
pcrt=$1 out=$2 runs=${3:-8} load=${4:-4}
tmp=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$tmp"; }
trap cleanup EXIT
for _ in $(seq "$load"); do (while :; do :; done) & pids+=($!); done
for _ in $(seq 180); do
  awk -v want="$load" '{ exit !($1 >= 0.75 * want) }' /proc/loadavg && break
  sleep 1
done
wrong_runs=0 wrong_fits=0
{
  echo "# pcrt calibrate with $load busy loops on $(nproc) cores"
  echo
  echo "commit $(git -C "$(dirname "$0")/.." rev-parse --short HEAD), ${LABEL:-}"
  echo
  echo "| run | load (1 min) | wrong fits |"
  echo "|---|---|---|"
  for k in $(seq "$runs"); do
    "$pcrt" calibrate >"$tmp/run.txt" 2>&1 || true
    wrong=$(grep WRONG "$tmp/run.txt" |
      sed -E 's/^ *([^ ]+) +([^ ]+) +expected (.*[^ ]) +best (.*[^ ]) +exponent.*/\1 (\2: \4)/' |
      paste -sd ';' - || true)
    n=$(grep -c WRONG "$tmp/run.txt" || true)
    [ "$n" -gt 0 ] && wrong_runs=$((wrong_runs + 1))
    wrong_fits=$((wrong_fits + n))
    echo "| $k | $(cut -d' ' -f1 /proc/loadavg) | ${wrong:-none} |"
  done
  echo
  echo "$wrong_runs of $runs runs had a wrong classification; $wrong_fits of $((runs * 10)) fits wrong."
} >"$out"
cat "$out"
