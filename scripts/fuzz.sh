#!/usr/bin/env bash
# Runs every libFuzzer target (tests/fuzz/) for a bounded time, seeded from real files: the small
# samples in tests/fuzz/seeds/ (among them command lines, a plan, jobs and runs files), the
# bad-input corpus (tests/bad_inputs/), the sweep configs, the committed results' small runs.jsonl
# files, and small files of the fetched scans in data/ when present. Fails on any finding (crash, sanitizer
# report, hang over 10 s, an error that is not an InputError naming the input); the finding's input
# is kept in fuzz-findings/.
# Usage: scripts/fuzz.sh [seconds per target (60)] [build dir (build-asan)]
# CI (scripts/test.sh) runs 60 s per target; a longer campaign: scripts/fuzz.sh 3600.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${2:-build-asan}
kinds=(ply xyz off rays spec json config plan jobs runs cli)
if [ ! -f "$build/build.ninja" ]; then
  CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPCRT_SANITIZE=ON \
    -DPCRT_FUZZ=ON >/dev/null
fi
cmake --build "$build" -j "$(nproc)" --target "${kinds[@]/#/pcrt_fuzz_}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p fuzz-findings
seed() {  # seed KIND FILE...: copy the existing, small ones into KIND's seed corpus
  local kind=$1; shift
  mkdir -p "$work/seeds/$kind"
  for f in "$@"; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -le 65536 ] && cp "$f" "$work/seeds/$kind/" || true
  done
}
shopt -s nullglob globstar
for kind in "${kinds[@]}"; do seed "$kind" tests/fuzz/seeds/"$kind"/*; done
seed ply tests/bad_inputs/*.ply data/**/*.ply
seed xyz tests/bad_inputs/*.xyz tests/bad_inputs/*.pwn data/**/*.xyz data/**/*.pwn
seed off tests/bad_inputs/*.off data/**/*.off
seed rays tests/bad_inputs/*.csv
seed spec tests/bad_inputs/*.spec
seed json tests/bad_inputs/*.json configs/*.json
seed config tests/bad_inputs/*.json configs/*.json
seed runs tests/bad_inputs/*.jsonl
seed plan tests/bad_inputs/plan_*.json
seed jobs tests/bad_inputs/jobs_*.json
# The committed results' runs files are large and all named runs.jsonl: their first 20 lines each,
# named after their folder.
for f in results/**/runs.jsonl; do
  head -n 20 "$f" >"$work/seeds/runs/$(dirname "$f" | tr / _).jsonl"
done

failed=0
for kind in "${kinds[@]}"; do
  mkdir -p "$work/corpus/$kind"
  log="$work/$kind.log"
  # The harness targets write scratch files under TMPDIR: inside $work, removed on exit.
  if TMPDIR="$work" "$build/bin/pcrt_fuzz_$kind" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="fuzz-findings/$kind-" \
    "$work/corpus/$kind" "$work/seeds/$kind" >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    echo "fuzz $kind: $runs executions in ${seconds} s, $(ls "$work/seeds/$kind" | wc -l) seeds, no finding"
  else
    echo "fuzz $kind: FINDING (input kept in fuzz-findings/):"
    grep -E 'ERROR|SUMMARY|error|abort|Test unit written' "$log" | head -20
    failed=1
  fi
done
exit "$failed"
