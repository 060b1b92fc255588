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
                  "datasets": ["sphere"], "grid": {"N": [500, 1000], "M": [64], "B": [0]}},
                 {"name": "ball_leaf", "kind": "render", "methods": ["ball_splat"],
                  "datasets": ["sphere"],
                  "grid": {"N": [4000], "M": [256], "B": [0],
                           "set.leaf_size": [2, 4, 8, 16, 32, 64, 128, 256]},
                  "fits": [{"claim": "ball_splat/leaf", "variable": "K", "x": "K",
                            "metric": "ops_ball_tests", "per": "ops_leaves_visited"}]}]}
JSON
"$mine" sweep "$tmp/sweep.json" --out "$tmp/sweep" --fit >/dev/null
# Its declared claim is judged like a built-in one, by the same rules: ball tests per visited
# leaf are the balls in the leaf, K itself, so the fitter must call it a loop check (y = x by
# construction), not a confirmation of O(K).
python3 - "$tmp/sweep/runs.jsonl" "$tmp/sweep/fits.json" <<'PY'
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
assert len(runs) == 10 and all(r["counters"]["ball_tests"] > 0 for r in runs), runs
fits = json.load(open(sys.argv[2]))
fits = fits if isinstance(fits, list) else fits["fits"]
mine = [f for f in fits if f["claim"] == "ball_splat/leaf"]
assert len(mine) == 1, fits
assert mine[0]["verdict"] == "loop_check", mine[0]
assert "error" not in mine[0] and mine[0]["points"] == 8, mine[0]
print("consumer: ball_splat/leaf judged:", mine[0]["verdict"], mine[0].get("reason", "")[:120])
PY
echo "consumer: ball_splat registered out of tree: listed, rendered, judged and swept"
