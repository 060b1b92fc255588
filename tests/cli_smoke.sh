#!/usr/bin/env bash
# render, trace, info, list and convert end to end, with the JSON shapes the issues promise.
set -euo pipefail
pcrt=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$pcrt" info sphere:n=2000 --json >"$dir/info.json"
python3 - "$dir/info.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["points"] == 2000 and j["attributes"] == ["position", "normal"], j
assert all(abs(v) <= 1 for v in j["bounds"]["min"] + j["bounds"]["max"])
assert 0.005 < j["mean_spacing"] < 0.05, j
PY
"$pcrt" render --method reference_splat --data torus:n=5000 --out "$dir/t.png" --width 48 --height 32 \
  --spp 2 --bounces 2 --threads 2 --stats "$dir/stats.json" --depth "$dir/d.png" --normals "$dir/n.png" >/dev/null
for f in t d n; do head -c 8 "$dir/$f.png" | od -An -c | grep -q 'P   N   G'; done
python3 - "$dir/stats.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["params"]["method"] == "reference_splat" and j["params"]["M"] == 48 * 32 and j["params"]["S"] == 2
assert j["counters"]["primary_rays"] == 48 * 32 * 2
assert "render" in j["timings"] and "prepare" in j["timings"]
PY
# --stream: the generator's points go straight into hubo_2006's quantized tree; the same frame,
# counters and build counts on 1 and 2 threads.
for t in 1 2; do
  "$pcrt" render --stream --method hubo_2006 --set quantized=1 --data sphere:n=30000 --out "$dir/s$t.png" \
    --width 32 --height 32 --threads $t --stats "$dir/stream$t.json" >/dev/null
done
cmp "$dir/s1.png" "$dir/s2.png"
python3 - "$dir/stream2.json" "$dir/stream1.json" <<'PY'
import json, sys
j, one = (json.load(open(p)) for p in sys.argv[1:])
assert j["counters"] == one["counters"] and j["prepare_counters"] == one["prepare_counters"]
assert j["params"]["streamed"] is True and j["params"]["N"] == 30000, j["params"]
assert j["counters"]["primary_rays"] == 32 * 32 and j["counters"]["ray_hits"] > 100, j["counters"]
assert "prepare/quantized_kd_tree" in j["timings"] and "prepare/spacing" in j["timings"]
assert 0 < j["process"]["estimated_scene_bytes"] < 30000 * 20
PY
# ... and a binary PLY file's, chunk by chunk: the same hits as the file read whole.
"$pcrt" convert sphere:n=30000 --out "$dir/s.ply" >/dev/null
for mode in "" --stream; do
  "$pcrt" render $mode --method hubo_2006 --set quantized=1 --data "$dir/s.ply" --out "$dir/f.png" \
    --width 32 --height 32 --threads 2 --stats "$dir/file$mode.json" >/dev/null
done
python3 - "$dir/file.json" "$dir/file--stream.json" <<'PY'
import json, sys
whole, streamed = (json.load(open(p)) for p in sys.argv[1:])
assert streamed["params"]["streamed"] is True and streamed["params"]["N"] == 30000
assert streamed["counters"]["ray_hits"] == whole["counters"]["ray_hits"] > 100, (streamed["counters"], whole["counters"])
PY
printf 'ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n0,0,5,0,0,1\n5,0,0,-2,0,0\n' >"$dir/rays.csv"
"$pcrt" trace --method reference_splat --data fibonacci_sphere:n=20000 --rays "$dir/rays.csv" --out "$dir/hits.csv" >/dev/null
python3 - "$dir/hits.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [r["hit"] for r in rows] == ["1", "0", "1"], rows
assert abs(float(rows[0]["t"]) - 4) < 0.01 and abs(float(rows[2]["t"]) - 4) < 0.01, rows
assert abs(float(rows[0]["nz"]) - 1) < 0.01
PY
# Every structure writes exactly brute force's HITS.csv (same leaf intersector).
python3 - "$dir/many.csv" <<'PY'
import random, sys, math
random.seed(3)
with open(sys.argv[1], "w") as f:
    f.write("ox,oy,oz,dx,dy,dz\n")
    for i in range(3000):
        o = [random.uniform(-2, 2) for _ in range(3)]
        d = [random.gauss(0, 1) for _ in range(3)]
        if i % 2 == 0:  # aimed at the torus from outside
            o = [3 * math.cos(i), 3 * math.sin(i), random.uniform(-1, 1)]
            t = [random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-0.3, 0.3)]
            d = [t[k] - o[k] for k in range(3)]
        f.write(",".join("%.6f" % v for v in o + d) + "\n")
PY
"$pcrt" trace --method reference_splat --structure brute_force --data torus:n=20000,seed=2 --rays "$dir/many.csv" --out "$dir/bf.csv" >/dev/null
for s in kd_tree octree sphere_tree grid; do  # structure parameters go through --set too
  "$pcrt" trace --method reference_splat --structure $s --data torus:n=20000,seed=2 --rays "$dir/many.csv" \
    --out "$dir/$s.csv" --stats "$dir/$s.json" >/dev/null
  cmp "$dir/bf.csv" "$dir/$s.csv" || { echo "FAIL: $s differs from brute_force"; exit 1; }
done
test "$(grep -c ',1,' "$dir/bf.csv")" -gt 500
"$pcrt" list --json | python3 -c '
import json, sys
j = json.load(sys.stdin)
m = {x["id"]: x for x in j["methods"]}
assert {"id", "paper", "structure", "needs", "parameters", "claims"} <= set(m["reference_splat"])
s = {x["id"]: x for x in j["structures"]}
assert {"brute_force", "kd_tree", "octree", "sphere_tree", "grid", "bvh"} <= set(s), s.keys()
assert [p["name"] for p in s["kd_tree"]["parameters"]] == ["leaf_size", "max_depth", "max_straddle", "split", "leaf_slabs"]
'
"$pcrt" convert torus:n=100 --out "$dir/t.ply" >/dev/null
test "$("$pcrt" info "$dir/t.ply" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["points"])')" = 100
# Reconstruction: JSON shape, mesh output, and the three engines agreeing ray by ray.
"$pcrt" reconstruct --method afsr --data sphere:n=2000 --out "$dir/s.ply" --json | python3 -c '
import json, sys
j = json.load(sys.stdin)
assert {"method", "points", "seconds", "cells", "facets", "triangles", "boundary_edges"} <= set(j), j
assert j["triangles"] == 2 * 2000 - 4 and j["boundary_edges"] == 0 and j["cells"] is None, j
'
"$pcrt" reconstruct --method delaunay --data skew_lines:n=100 --json | python3 -c '
import json, sys
j = json.load(sys.stdin); assert j["cells"] == 49 * 49 and j["triangles"] is None, j'
python3 - "$dir/sphere_rays.csv" <<'PY'
import random, sys
random.seed(3)
with open(sys.argv[1], "w") as f:
    f.write("ox,oy,oz,dx,dy,dz\n")
    for i in range(2000):
        t = [random.uniform(-1.2, 1.2), random.uniform(-1.2, 1.2), 0]
        f.write("0,0,4,%.6f,%.6f,-4\n" % (t[0], t[1]))
PY
for e in bvh cgal_aabb embree; do
  "$pcrt" trace --mesh "$dir/s.ply" --engine $e --rays "$dir/sphere_rays.csv" --out "$dir/mesh_$e.csv" >/dev/null
done
python3 - "$dir" <<'PY'
import csv, sys
rows = {e: list(csv.DictReader(open(f"{sys.argv[1]}/mesh_{e}.csv"))) for e in ("bvh", "cgal_aabb", "embree")}
hits = 0
for a, b, c in zip(rows["bvh"], rows["cgal_aabb"], rows["embree"]):
    assert a["hit"] == b["hit"] == c["hit"], (a, b, c)
    if a["hit"] == "1":
        hits += 1
        assert abs(float(a["t"]) - float(b["t"])) < 1e-4 and abs(float(a["t"]) - float(c["t"])) < 1e-4
assert hits > 1000, hits
PY
# Float images: a .exr name writes 32-bit OpenEXR (radiance, depth in scene units, signed normals).
"$pcrt" render --method reference_splat --data sphere:n=5000 --out "$dir/f.exr" --depth "$dir/d.exr" \
  --normals "$dir/n.EXR" --width 24 --height 16 >/dev/null
for f in f.exr d.exr n.EXR; do
  test "$(head -c 4 "$dir/$f" | od -An -tx1 | tr -d ' ')" = "762f3101" || { echo "FAIL: $f is not EXR"; exit 1; }
done
"$pcrt" render --mesh "$dir/s.ply" --engine bvh --out "$dir/mesh.png" --width 32 --height 32 --stats "$dir/mesh.json" >/dev/null
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert j["params"]["engine"] == "bvh" and j["counters"]["triangle_tests"] > 0' "$dir/mesh.json"
"$pcrt" crossover --data sphere:n=2000 --method goradia_2010 --width 32 --height 32 --reps 1 --json | python3 -c '
import json, sys
j = json.load(sys.stdin)
assert {"direct", "reconstruction", "crossover_frames", "frames"} <= set(j), j
assert j["reconstruction"]["triangles"] == 3996'
"$pcrt" list --json | python3 -c '
import json, sys
j = json.load(sys.stdin)
assert {r["id"] for r in j["reconstructions"]} == {"delaunay", "afsr"}
assert {e["id"] for e in j["mesh_engines"]} == {"bvh", "cgal_aabb", "embree"}
ids = {c["id"] for c in j["claims"]}
for need in ("kd_tree/build", "grid/query", "cai_2011/leaf", "tejada_2006/frame", "delaunay/worst",
             "mls/iterations", "goradia_2010/real_time", "reconstruction/crossover", "hubo_2006/requery",
             "tejada_2006/frame_reduced", "cai_2015/fan", "tejada_2007/iterations", "grid/occupancy",
             "brute_force/build", "direct/total", "reconstruction/total", "gift_wrapping/worst"):
    assert need in ids, need
assert all(c["source"] for c in j["claims"])
# Table 5.1 marks nine methods real-time; the others make no real-time claim.
assert {c["subject"] for c in j["claims"] if c["id"].endswith("/real_time")} == {"wald_seidel_2005", "tejada_2006", "hubo_2007", "tejada_2007", "kashyap_2010_splat", "goradia_2010", "kashyap_2010_implicit", "goradia_2011", "cai_2011"}
assert [c["id"] for c in j["claims"] if not c["tested"]] == ["goradia_2011/csm_prepass", "goradia_2011/csm_lookup", "gift_wrapping/uniform", "gift_wrapping/worst"]'
# A scene file: a glass point-cloud sphere and a mirror ball on a diffuse quad under a sphere light
# and a sampled environment; the stats name each object, and the frame is finite and lit.
cat >"$dir/scene.json" <<'JSON'
{"materials": {"glass": {"type": "dielectric", "eta": 1.5}, "floor": {"type": "diffuse"},
               "chrome": {"type": "rough_conductor", "roughness": 0.2}},
 "objects": [{"points": "sphere:n=4000", "method": "hubo_2006", "material": "glass",
              "transform": {"translate": [0, 0, 1]}},
             {"points": "sphere:n=2000", "method": "reference_splat", "structure": "kd_tree",
              "material": "chrome", "transform": {"translate": [2.2, 0, 0.6], "scale": 0.6}},
             {"quad": {"size": 10}, "material": "floor"}],
 "lights": [{"type": "sphere", "position": [2, -3, 6], "radius": 0.5, "radiance": 40},
            {"type": "environment", "radiance": 0.2}],
 "camera": {"eye": [0, -7, 3], "target": [0.5, 0, 0.8], "fov": 40}}
JSON
"$pcrt" render --scene "$dir/scene.json" --out "$dir/scene.exr" --width 32 --height 24 --spp 2 \
  --bounces 4 --stats "$dir/scene_stats.json" >/dev/null
python3 - "$dir/scene_stats.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
objs = j["params"]["objects"]
assert [o.get("method", o.get("engine")) for o in objs] == ["hubo_2006", "reference_splat", "bvh"], objs
assert [o["material"] for o in objs] == ["glass", "chrome", "floor"], objs
c = j["counters"]
assert c["primary_rays"] == 32 * 24 * 2 and c["bounce_rays"] > 0 and c["shadow_rays"] > 0, c
PY
# The white furnace of a convex cloud loses almost nothing.
"$pcrt" furnace --method reference_splat --data sphere:n=5000 --width 32 --height 32 --json >"$dir/f.json"
python3 - "$dir/f.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["object_pixels"] > 100 and 0.98 < j["mean"] <= 1.0 + 1e-6, j
assert 0 <= j["dark_pixels"] <= j["object_pixels"], j
PY
# A georeferenced cloud (a plane patch at 6x10^5, -4x10^6, as a LIDAR tile): rays and hits in the
# file's coordinates, the origin in --stats, convert writes it back in double.
python3 - "$dir/far.xyz" <<'PY'
import sys
with open(sys.argv[1], "w") as f:
    for i in range(100):
        for j in range(100):
            f.write("%.4f %.4f 57.25 0 0 1\n" % (600000.125 + 0.1 * i, -4000000.375 + 0.1 * j))
PY
printf 'ox,oy,oz,dx,dy,dz\n600004.0625,-3999996.4375,80,0,0,-1\n' >"$dir/far_rays.csv"
"$pcrt" trace --method reference_splat --data "$dir/far.xyz" --rays "$dir/far_rays.csv" \
  --out "$dir/far_hits.csv" --stats "$dir/far_stats.json" >/dev/null
"$pcrt" convert "$dir/far.xyz" --out "$dir/far.ply" --ascii >/dev/null
"$pcrt" info "$dir/far.xyz" --json >"$dir/far_info.json"
python3 - "$dir/far_hits.csv" "$dir/far_stats.json" "$dir/far.ply" "$dir/far_info.json" <<'PY'
import csv, json, sys
row = list(csv.DictReader(open(sys.argv[1])))[0]
assert row["hit"] == "1", row
p = [float(row[k]) for k in ("px", "py", "pz")]
# In float at 6e5 this point would be 6 cm off (the spacing there); in the local frame it is exact.
assert abs(p[0] - 600004.0625) < 1e-6 and abs(p[1] + 3999996.4375) < 1e-6, p
assert abs(p[2] - 57.25) < 1e-6 and abs(float(row["t"]) - 22.75) < 1e-5, row
assert json.load(open(sys.argv[2]))["params"]["origin"] == [600000, -4000000, 57], sys.argv[2]
text = open(sys.argv[3]).read()
assert "property double x" in text, "a georeferenced cloud is written back in double"
first = [float(v) for v in text.split("end_header\n")[1].split("\n")[0].split()[:3]]
assert abs(first[0] - 600000.125) < 1e-3 and abs(first[1] + 4000000.375) < 1e-3, first
info = json.load(open(sys.argv[4]))
assert info["origin"] == [600000, -4000000, 57], info
assert abs(info["bounds"]["min"][0] - 600000.125) < 1e-6 and abs(info["bounds"]["max"][1] + 3999990.475) < 1e-6, info
PY
# The same tile in a scene file (a quad, a light and the camera given in the file's coordinates)
# renders exactly as the tile moved to zero with everything else.
python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
with open(d + "/near.xyz", "w") as f:
    for i in range(100):
        for j in range(100):
            f.write("%.4f %.4f 0.25 0 0 1\n" % (0.125 + 0.1 * i, -0.375 + 0.1 * j))
def scene(points, o):
    at = lambda x, y, z: [o[0] + x, o[1] + y, o[2] + z]
    return {"materials": {"w": {"type": "diffuse", "albedo": 0.8}},
            "objects": [{"points": points, "method": "reference_splat", "material": "w"},
                        {"quad": {"size": 4}, "transform": {"translate": at(5, 5, 0.2)}}],
            "lights": [{"type": "point", "position": at(5, 5, 20), "intensity": 300}],
            "camera": {"eye": at(5, -10, 15), "target": at(5, 5, 0), "up": [0, 0, 1]}}
json.dump(scene("far.xyz", (600000, -4000000, 57)), open(d + "/far_scene.json", "w"))
json.dump(scene("near.xyz", (0, 0, 0)), open(d + "/near_scene.json", "w"))
PY
for s in far near; do
  "$pcrt" render --scene "$dir/${s}_scene.json" --out "$dir/${s}_scene.png" --width 64 --height 48 --spp 2 >/dev/null
done
cmp "$dir/far_scene.png" "$dir/near_scene.png"
# A file in 3D Gaussian Splatting's layout, as a trainer writes it (binary, zero normals, SH degree 1,
# opacity a logit, scales logs, rotation w x y z): flat particles on the plane z = 0. It loads with
# its particles, renders with grt_2024, and a ray down meets the plane at t = 5.
python3 - "$dir/splats.ply" <<'PY'
import math, struct, sys
names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"] + [f"f_rest_{i}" for i in range(9)] \
    + ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
rows = []
for i in range(40):
    for j in range(40):
        x, y = -1 + 0.05 * i, -1 + 0.05 * j
        rows.append([x, y, 0, 0, 0, 0, 0.5, 0.5, 0.5] + [0] * 9
                    + [math.log(0.9 / 0.1), math.log(0.03), math.log(0.03), math.log(1e-4), 1, 0, 0, 0])
with open(sys.argv[1], "wb") as f:
    f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % len(rows)
             + "".join(f"property float {n}\n" for n in names) + "end_header\n").encode())
    for r in rows:
        f.write(struct.pack("<%df" % len(names), *r))
PY
"$pcrt" info "$dir/splats.ply" --json >"$dir/splats_info.json"
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert j["points"] == 1600 and "gaussian" in j["attributes"], j' \
  "$dir/splats_info.json"
"$pcrt" render --method grt_2024 --data "$dir/splats.ply" --out "$dir/splats.png" --width 32 --height 32 \
  --view 0,0,1 --up 0,1,0 --stats "$dir/splats_stats.json" >/dev/null
python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["counters"]; assert c["ray_hits"] > 0 and c["particles_blended"] > 0, c' \
  "$dir/splats_stats.json"
printf 'ox,oy,oz,dx,dy,dz\n0.01,0.02,5,0,0,-1\n3,0,5,0,0,-1\n' >"$dir/splat_rays.csv"
"$pcrt" trace --method grt_2024 --data "$dir/splats.ply" --rays "$dir/splat_rays.csv" --out "$dir/splat_hits.csv" >/dev/null
python3 - "$dir/splat_hits.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [r["hit"] for r in rows] == ["1", "0"], rows
assert abs(float(rows[0]["t"]) - 5) < 1e-3 and abs(abs(float(rows[0]["nz"])) - 1) < 1e-3, rows
PY
# anchor: each blend candidate's primary hits against its paper structure's. On the octree (its
# paper's) the frame is its own; on the bvh (each splat in one leaf) the blends differ; the
# nearest-disc methods carry no such field (their hits are Embree's on every structure).
"$pcrt" anchor --data bumpy_sphere:n=6000,seed=2 --width 48 --height 48 --reps 1 --threads 2 --json \
  >"$dir/anchor.json"
python3 - "$dir/anchor.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
c = {(x["method"], x["structure"]): x for x in j["candidates"]}
for m in ("goradia_2010", "kashyap_2010_splat", "linsen_2007"):
    own = c[(m, "octree")]["frame_vs_paper"]
    assert own["paper_structure"] == "octree" and own["same_frame"], (m, own)
    assert own["apart_h_p95"] == 0 and own["one_only"] == 0, (m, own)
    bvh = c[(m, "bvh")]["frame_vs_paper"]
    assert not bvh["same_frame"] and bvh["other_hit"] > 0 and bvh["normal_deg_p95"] > 0, (m, bvh)
assert "frame_vs_paper" not in c[("reference_splat", "bvh")]
# The best of the papers' frames: a nearest-disc method, or a blend on a structure within rounding
# of its octree's frame (never the bvh's blends).
b = j["best_papers_frame"]
f = c[(b["method"], b["structure"])].get("frame_vs_paper")
assert f is None or (f["one_only"] == 0 and f["apart_h_p95"] <= 1e-3), b
PY
# A cloud whose secondary rays are empty sets (one point: primary rays only): reported as no rays,
# no rate or ratio, and the text names them.
"$pcrt" anchor --data sphere:n=1 --method reference_splat --structure bvh --width 16 --height 16 \
  --reps 1 --json >"$dir/anchor_one.json"
python3 - "$dir/anchor_one.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["candidates"][0]
assert c["bounce"]["rays"] == 0 and c["bounce"]["references"] == [], c["bounce"]
assert "mrays_per_s" not in c["shadow"] and c["primary"]["references"][0]["ratio"] > 0, c
PY
"$pcrt" anchor --data sphere:n=1 --method reference_splat --structure bvh --width 16 --height 16 \
  --reps 1 | grep -q "bounce: no rays"
echo "CLI smoke ok"
