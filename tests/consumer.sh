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
