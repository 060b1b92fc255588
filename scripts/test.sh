#!/usr/bin/env bash
# Sets up, fetches the real scans (tests use them when present), runs every test, then the
# operation-count gate: configs/ci.json against the committed results/baselines/ci.json, then the
# input readers under sanitizers and their fuzz targets.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh build
bash scripts/fetch_data.sh || echo "test: could not fetch the real scans; their tests are skipped"
ctest --test-dir build --output-on-failure -j "$(nproc)"
build/bin/pcrt check --config configs/ci.json --baseline results/baselines/ci.json
# Again with the SSE node tests CPUs without AVX2 run (the octree's, the bvh's and the triangle
# BVH's walks): the same counts, so the baseline holds on either CPU.
PCRT_NODE_LANES=sse build/bin/pcrt check --config configs/ci.json --baseline results/baselines/ci.json

# ASan + UBSan (clang, -fno-sanitize-recover=undefined): every unit and CLI test again, but the
# slowest (the Catch2 tests tagged [slow] and the ctest label `slow`: 20-50 s each here, 10-30x
# that under the sanitizers, on the same code the faster cases cover at smaller sizes) and the
# label `release_only`; then the bad-input corpus replayed in process and every libFuzzer target
# for PCRT_FUZZ_SECONDS (60) each. See docs/tests.md.
CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPCRT_SANITIZE=ON \
  -DPCRT_FUZZ=ON -DPCRT_PYTHON=OFF >/dev/null
cmake --build build-asan -j "$(nproc)"
# The [slow] Catch2 tests by name (ctest knows them by name only), as anchored regexes. Catch2's
# list commands exit with the number of tests listed, so the status is not an error here.
names=$(build-asan/bin/pcrt_tests "[slow]" --list-test-names-only || true)
slow=$(sed '/^$/d; s/[][\.*^$()+?{}|]/\\&/g' <<<"$names")
[ -n "$slow" ] || { echo "test: pcrt_tests lists no [slow] tests"; exit 1; }
pattern=$(printf '%s|' "${slow//$'\n'/|}")
echo "test: under ASan+UBSan, skipping the [slow] tests, label slow and label release_only"
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -LE 'slow|release_only' \
  -E "^(${pattern%|})\$"
bash tests/bad_inputs.sh replay build-asan/bin/pcrt_input_replay | tail -n 1
bash scripts/fuzz.sh "${PCRT_FUZZ_SECONDS:-60}" build-asan
