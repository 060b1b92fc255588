#!/bin/bash
# find_package(pcrt) from a downstream project: install this build into a temporary prefix,
# configure and build tests/consumer/ against it alone, and run it.
# usage: consumer.sh BUILD_DIR
set -euo pipefail
build=$1
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
launcher=$(grep -oP '^CMAKE_CXX_COMPILER_LAUNCHER:[A-Z]*=\K.*' "$build/CMakeCache.txt" || true)
cmake -S "$here/consumer" -B "$tmp/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" ${launcher:+-DCMAKE_CXX_COMPILER_LAUNCHER=$launcher} >/dev/null
cmake --build "$tmp/build" >/dev/null
# The consumer must have used the installed headers, not this source tree.
if grep -q -- "-I$(cd "$here/.." && pwd)\b" "$tmp/build/build.ninja"; then
  echo "consumer.sh: the consumer was compiled against the source tree, not the install" >&2
  exit 1
fi
"$tmp/build/consumer"
# The installed CLI and the report script beside it.
"$tmp/prefix/bin/pcrt" list >/dev/null
test -f "$tmp/prefix/share/pcrt/report.py"
# A method of one's own, out of tree (examples/out_of_tree_method): registered before
# pcrt::cli_main, it is listed, rendered, judged for accuracy and swept, and the sweep's child
# runs (this program again) know it too.
cmake -S "$here/../examples/out_of_tree_method" -B "$tmp/mine" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" ${launcher:+-DCMAKE_CXX_COMPILER_LAUNCHER=$launcher} >/dev/null
cmake --build "$tmp/mine" >/dev/null
mine="$tmp/mine/my_pcrt"
"$mine" list --json | python3 -c '
import json, sys
m = {x["id"]: x for x in json.load(sys.stdin)["methods"]}
assert "ball_splat" in m and "hubo_2006" in m, sorted(m)
assert [p["name"] for p in m["ball_splat"]["parameters"]] == ["radius_k"], m["ball_splat"]'
"$mine" render --method ball_splat --data sphere:n=2000 --out "$tmp/ball.png" --width 16 \
  --height 16 --stats "$tmp/ball.json" >/dev/null
"$mine" accuracy --method ball_splat --data sphere:n=20000 --rays 400 --json >"$tmp/acc.json"
python3 - "$tmp/ball.json" "$tmp/acc.json" <<'PY'
import json, sys
stats, acc = (json.load(open(p)) for p in sys.argv[1:])
assert stats["params"]["method"] == "ball_splat" and stats["counters"]["ball_tests"] > 0, stats
assert acc["hole_rate"] < 0.05, acc
PY
cat >"$tmp/sweep.json" <<'JSON'
{"name": "mine", "threads": 1, "repetitions": 1, "measure": "ops",
 "experiments": [{"name": "ball", "kind": "render", "methods": ["ball_splat"],
                  "datasets": ["sphere"], "grid": {"N": [500, 1000], "M": [64], "B": [0]}}]}
JSON
"$mine" sweep "$tmp/sweep.json" --out "$tmp/sweep" >/dev/null
python3 - "$tmp/sweep/runs.jsonl" <<'PY'
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
assert len(runs) == 2 and all(r["counters"]["ball_tests"] > 0 for r in runs), runs
PY
echo "consumer: ball_splat registered out of tree: listed, rendered, judged and swept"
