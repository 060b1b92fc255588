#!/usr/bin/env bash
# Sets up, fetches the real scans (tests use them when present), runs every test, then the
# operation-count gate: configs/ci.json against the committed results/baselines/ci.json.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh build
bash scripts/fetch_data.sh || echo "test: could not fetch the real scans; their tests are skipped"
ctest --test-dir build --output-on-failure -j "$(nproc)"
build/bin/pcrt check --config configs/ci.json --baseline results/baselines/ci.json
