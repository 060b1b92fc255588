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

# ASan + UBSan (clang, -fno-sanitize-recover=undefined) on the code that reads user input
# (pcrt_core: every reader, rays, generator specs, JSON): its unit tests, the bad-input corpus
# replayed in process, and every libFuzzer target for PCRT_FUZZ_SECONDS (60) each. Only pcrt_core
# is built here, not CGAL or the methods: see the README's "Tests".
CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPCRT_SANITIZE=ON \
  -DPCRT_FUZZ=ON >/dev/null
cmake --build build-asan -j "$(nproc)" --target pcrt_core_tests pcrt_input_replay
build-asan/bin/pcrt_core_tests
bash tests/bad_inputs.sh replay build-asan/bin/pcrt_input_replay | tail -n 1
bash scripts/fuzz.sh "${PCRT_FUZZ_SECONDS:-60}" build-asan
