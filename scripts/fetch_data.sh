#!/usr/bin/env bash
# Fetches the real scans into data/ (ignored by git): the data archive of Debian's libcgal-demo
# package (points_3/*.xyz|ply|pwn, meshes/*.off) and the Stanford bunny from npm's `bunny`.
# Idempotent: does nothing for what is already there.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p data
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

if [ ! -d data/cgal/points_3 ]; then
  echo "fetch: Debian libcgal-demo data archive"
  (cd "$tmp" && apt-get download libcgal-demo >/dev/null 2>&1 || { apt-get update -qq && apt-get download libcgal-demo >/dev/null; })
  dpkg-deb -x "$tmp"/libcgal-demo_*.deb "$tmp/deb"
  mkdir -p data/cgal
  tar -xzf "$tmp/deb/usr/share/doc/libcgal-dev/data.tar.gz" -C "$tmp" data/points_3 data/meshes
  mv "$tmp/data/points_3" "$tmp/data/meshes" data/cgal/
fi

if [ ! -f data/bunny/bunny.ply ]; then
  echo "fetch: npm bunny"
  # The machine image ships Node.js with npm; Debian's npm is only the fallback (it conflicts
  # with that Node.js build).
  command -v npm >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq npm >/dev/null
  (cd "$tmp" && npm pack bunny --silent >/dev/null)
  tar -xzf "$tmp"/bunny-*.tgz -C "$tmp"
  mkdir -p data/bunny
  # The package is a CommonJS module exporting positions and cells; write its vertices as PLY
  # (ascii, so anyone can read it) and keep the mesh as OFF for the reconstruction baselines.
  python3 - "$tmp/package/index.js" data/bunny <<'PY'
import json, re, sys
src = open(sys.argv[1]).read()
def grab(name):
    m = re.search(r"exports\.%s\s*=\s*(\[.*?\]\])" % name, src, re.S)
    return json.loads(m.group(1))
pos, cells = grab("positions"), grab("cells")
out = sys.argv[2]
with open(out + "/bunny.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\ncomment Stanford bunny from npm 'bunny'\nelement vertex %d\n" % len(pos))
    f.write("property float x\nproperty float y\nproperty float z\nend_header\n")
    for p in pos: f.write("%r %r %r\n" % tuple(p))
with open(out + "/bunny.off", "w") as f:
    f.write("OFF\n%d %d 0\n" % (len(pos), len(cells)))
    for p in pos: f.write("%r %r %r\n" % tuple(p))
    for c in cells: f.write("%d %s\n" % (len(c), " ".join(map(str, c))))
print("bunny: %d points, %d triangles" % (len(pos), len(cells)))
PY
fi
echo "data/: $(find data -type f | wc -l) files"
