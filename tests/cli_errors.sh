#!/usr/bin/env bash
# Every bad input must give exit status 1 and exactly one line on stderr naming the input; and a
# failed run must not damage a file that was already there.
set -u
pcrt=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fails=0
expect_error() {  # expect_error "what it must mention" pcrt-args...
  local want=$1; shift
  "$pcrt" "$@" >"$dir/out" 2>"$dir/err"
  local rc=$?
  local lines; lines=$(wc -l <"$dir/err")
  if [ "$rc" -ne 1 ] || [ "$lines" -ne 1 ] || ! grep -qF -- "$want" "$dir/err"; then
    echo "FAIL: pcrt $* -> rc=$rc, $lines stderr lines, wanted '$want':"; cat "$dir/err"; fails=$((fails + 1))
  else
    echo "ok: pcrt $* -> $(cat "$dir/err")"
  fi
}
printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 1 1\n' >"$dir/trunc.ply"
printf '0 0 0\nnan 1 1\n' >"$dir/nan.xyz"
printf 'ox,oy,oz,dx,dy,dz\n0,0,5,0,0,0\n' >"$dir/zero_dir.csv"
printf 'ox,oy,oz,dx,dy\n' >"$dir/bad_header.csv"
printf 'ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n0,0,5\n' >"$dir/short_row.csv"
printf 'ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n' >"$dir/rays.csv"

expect_error "trunc.ply: truncated" info "$dir/trunc.ply"
expect_error "nan.xyz: line 2" info "$dir/nan.xyz"
printf 'ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n' >"$dir/faces_first.ply"
expect_error "faces_first.ply: the face element comes before the vertex element" render --mesh "$dir/faces_first.ply" --out "$dir/a.png"
printf 'OFF\n3 1 0\n0 0 0\n1e-11 0 0\n0 1e-11 0\n3 0 1 2\n' >"$dir/speck.off"
expect_error "speck.off: the mesh spans 1.41e-11 units across" render --mesh "$dir/speck.off" --out "$dir/a.png"
printf '0 0 0\n1e-11 0 0\n0 1e-11 0\n' >"$dir/speck.xyz"
expect_error "speck.xyz: the cloud spans 1.41e-11 units across" render --method reference_splat --data "$dir/speck.xyz" --out "$dir/a.png"
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n1e-12 0 0 0 0 1\n' >"$dir/speck.ply"
expect_error "speck.ply: the cloud spans 1e-12 units across" render --method hubo_2006 --stream --set quantized=1 --data "$dir/speck.ply" --out "$dir/a.png"
expect_error "no such file" info "$dir/missing.ply"
expect_error "not a generator" info "cylinder:n=5"
expect_error "unknown parameter 'q'" info "sphere:q=1"
expect_error "unknown option '--bogus'" info sphere:n=10 --bogus
expect_error "unknown method 'nope'" render --method nope --data sphere:n=100 --out "$dir/a.png"
expect_error "unknown structure 'nope'" render --method reference_splat --structure nope --data sphere:n=100 --out "$dir/a.png"
expect_error "--set zzz: not a parameter" render --method reference_splat --data sphere:n=100 --out "$dir/a.png" --set zzz=1
expect_error "radius_k=0 is outside" render --method reference_splat --data sphere:n=100 --out "$dir/a.png" --set radius_k=0
# A note on a cloud read all the same (duplicates dropped) does not join a later error's line.
printf '0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n' >"$dir/dup.xyz"
expect_error "radius_k=0 is outside" render --method reference_splat --data "$dir/dup.xyz" --out "$dir/a.png" --set radius_k=0
if ! "$pcrt" info "$dir/dup.xyz" 2>&1 >/dev/null | grep -q "dropped 1 exact duplicate points"; then echo "FAIL: the duplicates note is lost on success"; fails=$((fails + 1)); fi
# An unknown node-lanes choice is refused rather than running the AVX2 walks under another name.
PCRT_NODE_LANES=avx expect_error "PCRT_NODE_LANES=avx: unknown" render --method reference_splat --structure bvh --data sphere:n=100 --out "$dir/a.png"
expect_error "--width 0 is outside" render --method reference_splat --data sphere:n=100 --out "$dir/a.png" --width 0
expect_error "'x' is not an integer" render --method reference_splat --data sphere:n=100 --out "$dir/a.png" --spp x
expect_error "--out is required" render --method reference_splat --data sphere:n=100
# A cloud that will not fit: out of memory names the input (under a 600 MB address-space limit);
# a scene that will not fit is refused before any work, with the estimate (issue 16; leaf-order
# disc blocks on the kd-tree: 142 B/point over the cloud, where the default needs 38). ASan
# reserves terabytes of shadow address space, which the limits forbid: skipped there, said.
if [ -n "${PCRT_SANITIZED:-}" ]; then
  echo "cli_errors: the three out-of-memory cases are skipped under AddressSanitizer"
else
  (fails=0; ulimit -v 600000 && expect_error "out of memory: sphere:n=200000000 is too large" info sphere:n=200000000; exit "$fails")
  [ $? -eq 0 ] || fails=$((fails + 1))
  # A stream too large for its records (16 B a point) is refused before its first point is drawn.
  (fails=0; ulimit -v 600000 && expect_error "out of memory: sphere:n=100000000 streamed into hubo_2006 (100000000 points) is too large" render --stream --method hubo_2006 --set quantized=1 --data sphere:n=100000000 --out "$dir/a.png"; exit "$fails")
  [ $? -eq 0 ] || fails=$((fails + 1))
  (fails=0; ulimit -v 500000 && expect_error "out of memory: sphere:n=5000000 with reference_splat on 5000000 points is too large for this machine: about 0.68 GiB needed (estimate)" render --method reference_splat --structure kd_tree --set disc_blocks=1 --data sphere:n=5000000 --out "$dir/a.png"; exit "$fails")
  [ $? -eq 0 ] || fails=$((fails + 1))
fi
# A file too large to read whole (1 TiB, sparse: no disk used) is refused before its first byte;
# streamed, its line of NUL bytes is too long, and a PLY of them has no header.
truncate -s 1T "$dir/huge.xyz" && cp --sparse=always "$dir/huge.xyz" "$dir/huge.ply"
expect_error "out of memory: $dir/huge.xyz (1099511627776 bytes, read whole) is too large" info "$dir/huge.xyz"
expect_error "out of memory: $dir/huge.ply (1099511627776 bytes, read whole) is too large" render --method reference_splat --data "$dir/huge.ply" --out "$dir/a.png"
expect_error "huge.xyz: line 1: longer than 4 MiB" render --stream --method hubo_2006 --set quantized=1 --data "$dir/huge.xyz" --out "$dir/a.png"
expect_error "huge.ply: PLY header has no end_header line" render --stream --method hubo_2006 --set quantized=1 --data "$dir/huge.ply" --out "$dir/a.png"
rm -f "$dir/huge.xyz" "$dir/huge.ply"
# --stream: only the methods that prepare from a stream, only generators with normals.
expect_error "sphere:n=1000: method reference_splat does not prepare from a stream" render --stream --method reference_splat --data sphere:n=1000 --out "$dir/a.png"
expect_error "method hubo_2006 does not prepare from a stream with these parameters" render --stream --method hubo_2006 --data sphere:n=1000 --out "$dir/a.png"
expect_error "ball:n=1000': ball has no normals" render --stream --method hubo_2006 --set quantized=1 --data ball:n=1000 --out "$dir/a.png"
"$pcrt" convert sphere:n=100 --out "$dir/ascii.ply" --ascii >/dev/null
head -n 20 "$dir/ascii.ply" >"$dir/ascii_cut.ply"  # the 11 header lines and 9 of 100 vertices
expect_error "ascii_cut.ply: truncated: file ends at 'vertex' element 9 of 100" render --stream --method hubo_2006 --set quantized=1 --data "$dir/ascii_cut.ply" --out "$dir/a.png"
expect_error "nan.xyz: has no normals (x y z only): only clouds with normals stream" render --stream --method hubo_2006 --set quantized=1 --data "$dir/nan.xyz" --out "$dir/a.png"
expect_error "--stream does not apply to --mesh" render --stream --mesh "$dir/nan.xyz" --out "$dir/a.png"
# The papers' octree's parameters beside loose=1 contradict it.
expect_error "loose=1 places each item once; stop_refs, compact_refs, child_bounds and leaf_slabs apply to loose=0 only" render --method goradia_2010 --set loose=1 --set compact_refs=1 --data sphere:n=2000 --out "$dir/c.png"
expect_error "loose=1 places each item once" render --method goradia_2010 --set loose=1 --set stop_refs=2 --data sphere:n=2000 --out "$dir/c.png"
# Leaf-order disc blocks on the octree's compact references, which are decoded per leaf.
expect_error "disc_blocks=1 (leaf order) needs the structure's leaves as pieces of one reference array" render --method reference_splat --structure octree --set compact_refs=1 --set disc_blocks=1 --data sphere:n=2000 --out "$dir/c.png"
expect_error "zero_dir.csv: line 2: zero direction" trace --method reference_splat --data sphere:n=100 --rays "$dir/zero_dir.csv" --out "$dir/h.csv"
expect_error "bad_header.csv: line 1" trace --method reference_splat --data sphere:n=100 --rays "$dir/bad_header.csv" --out "$dir/h.csv"
expect_error "short_row.csv: line 3" trace --method reference_splat --data sphere:n=100 --rays "$dir/short_row.csv" --out "$dir/h.csv"
expect_error "--out $dir/no/such/dir/h.csv: folder $dir/no/such/dir does not exist" trace --method reference_splat --data sphere:n=100 --rays "$dir/rays.csv" --out "$dir/no/such/dir/h.csv"

printf "0 0 0\\n1 0 0\\n0 1 0\\n1 1 1\\n" >"$dir/four.xyz"
expect_error "no exact surface (a file, or a generator without one); accuracy needs a generator" accuracy --method reference_splat --data "$dir/four.xyz"
expect_error "traces through its own embree_bvh" trace --method embree_oriented_disc --structure kd_tree --data sphere:n=100 --rays "$dir/rays.csv" --out "$dir/h.csv"
expect_error "--rays 0 is outside" accuracy --method reference_splat --data sphere:n=100 --rays 0
expect_error "--data is required" anchor

# Reconstruction and meshes.
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' >"$dir/badface.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n' >"$dir/nofaces.ply"
printf "0 0 0\n1 0 0\n0 1 0\n" >"$dir/three.xyz"
expect_error "three.xyz: delaunay needs at least 4 points" reconstruct --method delaunay --data "$dir/three.xyz"
expect_error "plane:n=100: delaunay: all 100 points are coplanar" reconstruct --method delaunay --data plane:n=100
expect_error "plane:n=100: afsr: all 100 points are coplanar" reconstruct --method afsr --data plane:n=100
expect_error "unknown reconstruction 'poisson'" reconstruct --method poisson --data sphere:n=100
expect_error "makes no triangle mesh" reconstruct --method delaunay --data sphere:n=100 --out "$dir/m.ply"
expect_error "badface.ply: face 0 names vertex 7" render --mesh "$dir/badface.ply" --out "$dir/a.png"
expect_error "nofaces.ply: the mesh has no faces" render --mesh "$dir/nofaces.ply" --out "$dir/a.png"
expect_error "--method does not apply to --mesh" render --mesh "$dir/badface.ply" --method goradia_2010 --out "$dir/a.png"
expect_error "unknown mesh engine 'nope'" trace --mesh "$dir/m.ply" --engine nope --rays "$dir/rays.csv" --out "$dir/h.csv"
expect_error "--engine applies only to --mesh" render --method reference_splat --data sphere:n=100 --engine bvh --out "$dir/a.png"
expect_error "density does not apply to skew_lines" info skew_lines:n=10,density=0.5

# A failing run leaves an existing output untouched.
echo "precious" >"$dir/keep.png"
"$pcrt" render --method reference_splat --data "$dir/trunc.ply" --out "$dir/keep.png" 2>/dev/null
if [ "$(cat "$dir/keep.png")" != "precious" ]; then echo "FAIL: a failed render changed its output"; fails=$((fails + 1)); fi
# Mesh ground truth and frame comparison: bad meshes, sampling specs and option mixes.
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$dir/tri.off"
expect_error "no_mesh.off" accuracy --method reference_splat --truth "$dir/no_mesh.off"
expect_error "trunc.ply" accuracy --method reference_splat --truth "$dir/trunc.ply"
expect_error "normals must be exact, estimated or none" accuracy --method hubo_2006 --truth "$dir/tri.off" --sample normals=guess
expect_error "--sample 'n=3'" accuracy --method hubo_2006 --truth "$dir/tri.off" --sample n=3
expect_error "give --data or --truth, not both" accuracy --method hubo_2006 --truth "$dir/tri.off" --data sphere:n=100
expect_error "apply only to --truth" accuracy --method hubo_2006 --data sphere:n=100 --sample n=100
expect_error "mesh engine" accuracy --method hubo_2006 --truth "$dir/tri.off" --truth-engine nope
expect_error "--truth MESH is required" compare --method hubo_2006 --out "$dir/d.png"
expect_error "does not apply" compare --method hubo_2006 --truth "$dir/tri.off" --data sphere:n=100 --out "$dir/d.png"
# Every output is checked before the work and written only when everything has succeeded (issue
# 14: render wrote out.png, then failed on --stats DIR or --depth; trace did the same to hits.csv).
mkdir "$dir/statsdir"
keep_outputs() {  # keep_outputs "what it must mention" OUTPUT... -- pcrt-args...
  local want=$1; shift
  local outs=()
  while [ "$1" != "--" ]; do outs+=("$1"); echo "precious" >"$1"; shift; done
  shift
  expect_error "$want" "$@"
  for o in "${outs[@]}"; do
    if [ "$(cat "$o")" != "precious" ]; then echo "FAIL: pcrt $* changed $o"; fails=$((fails + 1)); fi
  done
}
render=(render --method reference_splat --data sphere:n=200 --width 8 --height 8)
keep_outputs "--stats $dir/statsdir: is a directory" "$dir/keep.png" -- "${render[@]}" --out "$dir/keep.png" --stats "$dir/statsdir"
keep_outputs "--depth $dir/nonexistent/d.png: folder" "$dir/keep.png" -- "${render[@]}" --out "$dir/keep.png" --depth "$dir/nonexistent/d.png"
keep_outputs "--depth: an empty file name" "$dir/keep.png" -- "${render[@]}" --out "$dir/keep.png" --depth ''
keep_outputs "--out: an empty file name" "$dir/keep.png" -- "${render[@]}" --out '' --depth "$dir/keep.png"
keep_outputs "--out $dir/statsdir: is a directory" "$dir/keep.png" -- "${render[@]}" --out "$dir/statsdir" --normals "$dir/keep.png"
keep_outputs "--stats $dir/statsdir: is a directory" "$dir/hits.csv" -- trace --method reference_splat --data sphere:n=200 --rays "$dir/rays.csv" --out "$dir/hits.csv" --stats "$dir/statsdir"
keep_outputs "--out $dir/statsdir: is a directory" "$dir/keep.ply" -- convert sphere:n=10 --out "$dir/statsdir"
keep_outputs "--images" "$dir/diff.png" -- compare --method reference_splat --truth "$dir/tri.off" --out "$dir/diff.png" --images "$dir/nonexistent/x"
if compgen -G "$dir/*.tmp.*" >/dev/null; then echo "FAIL: temporaries left: $(ls "$dir"/*.tmp.*)"; fails=$((fails + 1)); fi
# Scene files: every malformed value names the file and the key.
scene() { printf '%s' "$2" >"$dir/$1.json"; }
scene s_keys '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "point", "position": [0,0,1], "intensity": 1}], "colour": 1}'
scene s_material '{"materials": {"m": {"type": "velvet"}}, "objects": [{"quad": {"size": 1}, "material": "m"}], "lights": [{"type": "sky"}]}'
scene s_missing_material '{"objects": [{"quad": {"size": 1}, "material": "glass"}], "lights": [{"type": "sky"}]}'
scene s_two_kinds '{"objects": [{"quad": {"size": 1}, "mesh": "x.off"}], "lights": [{"type": "sky"}]}'
scene s_bad_eta '{"materials": {"g": {"type": "dielectric", "eta": -1}}, "objects": [{"quad": {"size": 1}}], "lights": [{"type": "sky"}]}'
scene s_nan '{"objects": [{"quad": {"size": 1}, "transform": {"scale": 0}}], "lights": [{"type": "sky"}]}'
scene s_no_lights '{"objects": [{"quad": {"size": 1}}], "lights": []}'
scene s_light '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "laser"}]}'
scene s_radius '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "sphere", "position": [0,0,1], "radiance": 1}]}'
scene s_method '{"objects": [{"points": "sphere:n=100", "method": "nope"}], "lights": [{"type": "sky"}]}'
scene s_env '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "environment", "file": "missing.exr"}]}'
scene s_camera '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "sky"}], "camera": {"eye": [0,0,1], "target": [0,0,1]}}'
printf '{"objects": [' >"$dir/s_trunc.json"
sr=(render --width 8 --height 8 --out "$dir/s.png" --scene)
expect_error "s_keys.json: colour is not a key here" "${sr[@]}" "$dir/s_keys.json"
expect_error "s_material.json: materials.m.type (unknown material 'velvet'" "${sr[@]}" "$dir/s_material.json"
expect_error "objects[0].material 'glass' is not in \"materials\"" "${sr[@]}" "$dir/s_missing_material.json"
expect_error "objects[0] needs exactly one of" "${sr[@]}" "$dir/s_two_kinds.json"
expect_error "materials.g.eta must lie in" "${sr[@]}" "$dir/s_bad_eta.json"
expect_error "objects[0].transform.scale must lie in" "${sr[@]}" "$dir/s_nan.json"
expect_error "lights must be a non-empty array" "${sr[@]}" "$dir/s_no_lights.json"
expect_error "'laser' is not a light" "${sr[@]}" "$dir/s_light.json"
expect_error "(sphere) needs \"radius\"" "${sr[@]}" "$dir/s_radius.json"
# A sphere light's radius squares in float: bounded by the coordinate range, and one near the
# largest allowed, a light around the whole scene, still lights it (finite, not black).
scene s_huge_light '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "sphere", "position": [0,0,0], "radius": 1e20, "radiance": 1}]}'
expect_error "s_huge_light.json: lights[0].radius must lie in [1e-09, 1e+12]" "${sr[@]}" "$dir/s_huge_light.json"
scene s_big_light '{"objects": [{"quad": {"size": 1}}], "lights": [{"type": "sphere", "position": [0,0,0], "radius": 5e11, "radiance": 1}], "camera": {"eye": [0,-3,1], "target": [0,0,0]}}'
if "$pcrt" "${sr[@]}" "$dir/s_big_light.json" --stats "$dir/big_light.json" >/dev/null 2>"$dir/err" &&
  python3 -c 'import json, math, sys; m = json.load(open(sys.argv[1]))["image_mean"]; sys.exit(not all(v is not None and math.isfinite(v) and v > 0 for v in m))' "$dir/big_light.json"; then
  echo "ok: a sphere light of radius 5e11 around the scene lights it"
else
  echo "FAIL: a sphere light of radius 5e11: $(cat "$dir/err") $(cat "$dir/big_light.json" 2>/dev/null | head -c 300)"; fails=$((fails + 1))
fi
expect_error "s_method.json: objects[0] (unknown method 'nope'" "${sr[@]}" "$dir/s_method.json"
expect_error "missing.exr" "${sr[@]}" "$dir/s_env.json"
expect_error "camera eye and target must differ" "${sr[@]}" "$dir/s_camera.json"
expect_error "s_trunc.json" "${sr[@]}" "$dir/s_trunc.json"
# Positions beyond the coordinate range, and transforms that would take the scene's rays beyond it
# in an object's frame, where Embree aborts on a ray past about 1.8e18.
scene s_far_eye '{"objects": [{"points": "sphere:n=100", "method": "embree_oriented_disc"}], "lights": [{"type": "sky"}], "camera": {"eye": [1e19,1,1], "target": [0,0,0]}}'
scene s_far_move '{"objects": [{"points": "sphere:n=100", "method": "embree_oriented_disc", "transform": {"translate": [1e19,0,0]}}], "lights": [{"type": "sky"}]}'
scene s_tiny_far '{"objects": [{"points": "sphere:n=100", "method": "embree_oriented_disc", "transform": {"scale": 1e-6, "translate": [-9e11,0,0]}}, {"quad": {"size": 1}, "transform": {"translate": [9e11,0,0]}}], "lights": [{"type": "sky"}]}'
expect_error "s_far_eye.json: camera.eye[0] must lie in [-1e+12, 1e+12]" "${sr[@]}" "$dir/s_far_eye.json"
expect_error "s_far_move.json: objects[0].transform.translate[0] must lie in" "${sr[@]}" "$dir/s_far_move.json"
expect_error "s_tiny_far.json: objects[0].transform puts the scene's rays beyond" "${sr[@]}" "$dir/s_tiny_far.json"
expect_error "--ray-epsilon must be <= 1e+12" render --method embree_oriented_disc --data sphere:n=100 --width 8 --height 8 --out "$dir/s.png" --ray-epsilon 1e19
expect_error "--ray-epsilon must be <= 1e+12" furnace --method embree_oriented_disc --data sphere:n=100 --width 8 --height 8 --ray-epsilon 1e19
# A direction of huge components is a direction: normalised, not squared to infinity.
scene s_big_up '{"objects": [{"quad": {"size": 1}, "transform": {"rotate": {"axis": [1e30,1e30,1e30], "degrees": 30}}}], "lights": [{"type": "sky"}], "camera": {"eye": [0,-3,1], "target": [0,0,0], "up": [0,0,1e30]}}'
if "$pcrt" "${sr[@]}" "$dir/s_big_up.json" >/dev/null 2>"$dir/err"; then echo "ok: a scene with an up and an axis of 1e30"; else echo "FAIL: up or axis of 1e30: $(cat "$dir/err")"; fails=$((fails + 1)); fi
# The same on the command line: --view and --up of huge components frame as their unit vectors.
same_frame() {  # same_frame "what" args-a -- args-b: the two renders write the same image
  local what=$1; shift
  local a=() b=(); while [ "$1" != -- ]; do a+=("$1"); shift; done; shift; b=("$@")
  local r=(render --method reference_splat --data sphere:n=200 --width 16 --height 16)
  if "$pcrt" "${r[@]}" "${a[@]}" --out "$dir/frame_a.png" >/dev/null 2>"$dir/err" &&
    "$pcrt" "${r[@]}" "${b[@]}" --out "$dir/frame_b.png" >/dev/null 2>>"$dir/err" &&
    cmp -s "$dir/frame_a.png" "$dir/frame_b.png"; then
    echo "ok: $what"
  else
    echo "FAIL: $what: $(cat "$dir/err")"; fails=$((fails + 1))
  fi
}
same_frame "--view 1e39,1e39,0 frames as --view 1,1,0" --view 1e39,1e39,0 -- --view 1,1,0
same_frame "--view 1e20,1e20,1e20 frames as --view 1,1,1" --view 1e20,1e20,1e20 -- --view 1,1,1
same_frame "--up 0,0,1e20 frames as --up 0,0,1" --up 0,0,1e20 -- --up 0,0,1
same_frame "--view 1e-200,-1e-200,0 frames as --view 1,-1,0" --view 1e-200,-1e-200,0 -- --view 1,-1,0
expect_error "--view: '0,0,0' is the zero vector" "${render[@]}" --out "$dir/a.png" --view 0,0,0
expect_error "--up: 'inf' is not finite" "${render[@]}" --out "$dir/a.png" --up 0,0,inf
expect_error "--method does not apply to --scene" "${sr[@]}" "$dir/s_keys.json" --method reference_splat
# A scene file's camera fixes the view as its objects fix the method.
expect_error "--view does not apply to --scene $dir/s_big_up.json" "${sr[@]}" "$dir/s_big_up.json" --view 1,0,0
expect_error "--up does not apply to --scene $dir/s_big_up.json" "${sr[@]}" "$dir/s_big_up.json" --up 0,1,0
expect_error "give --data, --mesh or --truth" furnace --method reference_splat --data sphere:n=100 --truth "$dir/tri.off"
expect_error "--exact traces a generator's own surface: give --data only" furnace --exact --method reference_splat --data sphere:n=100
expect_error "tri.off: no exact surface (a file, or a generator without one); --exact needs a generator with an exact surface" furnace --exact --data "$dir/tri.off"
expect_error "skew_lines:n=100: no exact surface" accuracy --method hubo_2006 --data skew_lines:n=100
expect_error "max_alpha 0.5 and opacity 0 (0: 1) give flat particles (init=flat) a peak opacity of 0.5: it must be above 0.5" render --method ever_2024 --data sphere:n=200 --width 8 --height 8 --out "$dir/e.png" --set max_alpha=0.5
# Registry and reader errors inside a config name the config and the experiment (issue 29).
printf '{"experiments": [{"kind": "render", "methods": ["reference_splat"], "structures": ["NaN"], "datasets": ["sphere"], "grid": {"N": [100], "M": [16], "B": [1]}}]}' >"$dir/c_structure.json"
expect_error "c_structure.json: experiments[0]: unknown structure 'NaN'" sweep "$dir/c_structure.json" --out "$dir/c_structure_out"
printf '{"experiments": [{"kind": "reconstruct", "reconstructions": ["nope"], "datasets": ["sphere"], "grid": {"N": [100]}}]}' >"$dir/c_recon.json"
expect_error "c_recon.json: experiments[0]: unknown reconstruction 'nope'" sweep "$dir/c_recon.json" --out "$dir/c_recon_out"
printf '{"experiments": [{"kind": "render", "methods": ["reference_splat"], "datasets": ["missing.ply"], "grid": {"N": [100], "M": [16], "B": [1]}}]}' >"$dir/c_data.json"
expect_error "c_data.json: experiments[0]: $dir/missing.ply" sweep "$dir/c_data.json" --out "$dir/c_data_out"
# A triangulation needs 4 points: a crossover (or reconstruct) grid below that is refused.
printf '{"experiments": [{"kind": "crossover", "methods": ["reference_splat"], "datasets": ["sphere"], "grid": {"N": [3], "M": [16]}}]}' >"$dir/c_cross3.json"
expect_error "c_cross3.json: experiments[0]: N = 3 is impossible (a whole number in [4," sweep "$dir/c_cross3.json" --out "$dir/c_cross3_out"
# A config of absurd size is refused before any run, with its size and estimate (issue 29).
printf '{"experiments": [{"kind": "render", "methods": ["reference_splat"], "datasets": ["sphere"], "replicates": 100, "grid": {"N": [%s], "M": [16], "B": [1]}}]}' "$(seq -s, 100 1 1100)" >"$dir/c_huge.json"
expect_error "c_huge.json: 100100 runs, about" sweep "$dir/c_huge.json" --out "$dir/c_huge_out"
if [ -e "$dir/c_huge_out" ]; then echo "FAIL: a refused sweep made its folder"; fails=$((fails + 1)); fi
# Beyond what any config may expand to: refused before the points are made, in well under a
# second (10^12 points would need terabytes).
printf '{"experiments": [{"kind": "render", "methods": ["reference_splat"], "datasets": ["sphere"], "grid": {"N": [%s], "M": [%s], "S": [%s], "B": [1]}}]}' "$(seq -s, 1 10000)" "$(seq -s, 1 10000)" "$(seq -s, 1 10000)" >"$dir/c_absurd.json"
expect_error "c_absurd.json: experiments[0].grid: 1e+12 points, more than a config may expand to (1000000 runs)" sweep "$dir/c_absurd.json" --out "$dir/c_absurd_out" --no-limit
printf '{"experiments": [{"kind": "render", "methods": ["surveyed"], "datasets": ["sphere"], "replicates": 100, "grid": {"N": [%s], "M": [16], "B": [1]}}]}' "$(seq -s, 100 1 1100)" >"$dir/c_absurd2.json"
expect_error "c_absurd2.json: experiments[0]: the config expands to" sweep "$dir/c_absurd2.json" --out "$dir/c_absurd_out" --no-limit
# Scenes in sweeps: the config and experiment named, and the scene's own key.
scene s_unswept '{"objects": [{"points": "plane:n=100", "method": "reference_splat"}], "lights": [{"type": "sky"}]}'
printf '{"experiments": [{"kind": "render", "methods": ["reference_splat"], "datasets": ["plane"], "scene": "s_unswept.json", "grid": {"N": [100], "M": [16], "B": [1]}}]}' >"$dir/c_scene.json"
expect_error "c_scene.json: experiments[0]: scene: $dir/s_unswept.json: objects mark no point cloud \"swept\": true" sweep "$dir/c_scene.json" --out "$dir/c_scene_out"
# Outputs: a device or FIFO is refused and left as it was, never replaced by a file; a symbolic
# link is written through to its target and stays a link; an output that is an input is refused.
mkfifo "$dir/fifo"
expect_error "--out $dir/fifo: is a device, FIFO or socket" "${render[@]}" --out "$dir/fifo"
# An output named as another format than the one written is refused (convert --out x.xyz once
# wrote a PLY that pcrt could not read back).
expect_error "--out $dir/x.jpg: writes .png or .exr files" "${render[@]}" --out "$dir/x.jpg"
expect_error "--depth $dir/d.tif: writes .png or .exr files" "${render[@]}" --out "$dir/x.png" --depth "$dir/d.tif"
expect_error "--out $dir/x.xyz: writes .ply files" convert sphere:n=10 --out "$dir/x.xyz"
expect_error "--out $dir/m.off: writes .ply files" reconstruct --method delaunay --data sphere:n=100 --out "$dir/m.off"
expect_error "--out $dir/f.jpg: writes .png or .exr files" furnace --method reference_splat --data sphere:n=100 --width 8 --height 8 --out "$dir/f.jpg"
expect_error "--out $dir/c.exr: writes .png files" compare --method hubo_2006 --truth "$dir/tri.off" --width 8 --height 8 --out "$dir/c.exr"
[ -p "$dir/fifo" ] || { echo "FAIL: the FIFO was replaced"; fails=$((fails + 1)); }
expect_error "--stats /dev/null: is a device, FIFO or socket" "${render[@]}" --out "$dir/dev.png" --stats /dev/null
[ -c /dev/null ] || { echo "FAIL: /dev/null is no longer a device"; fails=$((fails + 1)); }
[ -e "$dir/dev.png" ] && { echo "FAIL: an output was written before the refusal"; fails=$((fails + 1)); }
ln -s "$dir/target.png" "$dir/link.png"
if "$pcrt" "${render[@]}" --out "$dir/link.png" >/dev/null 2>&1 && [ -L "$dir/link.png" ] &&
  head -c 8 "$dir/target.png" | od -An -c | grep -q 'P   N   G'; then
  echo "ok: an output through a symbolic link lands on its target, the link stays"
else
  echo "FAIL: an output through a symbolic link"; fails=$((fails + 1))
fi
ln -s "$dir/loop_b" "$dir/loop_a" && ln -s "$dir/loop_a" "$dir/loop_b"
expect_error "loop_a: a loop of symbolic links" "${render[@]}" --out "$dir/loop_a"
"$pcrt" convert sphere:n=100 --out "$dir/in.ply" >/dev/null
cp "$dir/in.ply" "$dir/in.copy"
ln -s "$dir/in.ply" "$dir/in_link.ply"
expect_error "--out $dir/in.ply: is also the input --data" render --method reference_splat --data "$dir/in.ply" --out "$dir/in.ply"
expect_error "--stats $dir/in_link.ply: is also the input --data" render --method reference_splat --data "$dir/in.ply" --out "$dir/x.png" --stats "$dir/in_link.ply"
expect_error "--out $dir/rays.csv: is also the input --rays" trace --method reference_splat --data sphere:n=100 --rays "$dir/rays.csv" --out "$dir/rays.csv"
expect_error "is also the input DATA" convert "$dir/in.ply" --out "$dir/in_link.ply"
expect_error "--out $dir/in.ply: is also the input --data" reconstruct --method afsr --data "$dir/in.ply" --out "$dir/in.ply"
expect_error "--out $dir/in.ply: is also the input --data" furnace --method reference_splat --data "$dir/in.ply" --out "$dir/in.ply" --width 8 --height 8
expect_error "--out $dir/tri.off: is also the input --truth" compare --method reference_splat --truth "$dir/tri.off" --out "$dir/tri.off" --width 8 --height 8
# Two outputs naming one file would keep only the last one written.
expect_error "--stats $dir/./two.png: is also the output --out $dir/two.png" render --method reference_splat --data sphere:n=100 --width 8 --height 8 --out "$dir/two.png" --stats "$dir/./two.png"
expect_error "--stats $dir/two.csv: is also the output --out $dir/two.csv" trace --method reference_splat --data sphere:n=100 --rays "$dir/rays.csv" --out "$dir/two.csv" --stats "$dir/two.csv"
# Files a scene reads are inputs too, known once the scene is read.
scene s_reads "{\"objects\": [{\"points\": \"in.ply\", \"method\": \"reference_splat\"}, {\"mesh\": \"tri.off\"}], \"lights\": [{\"type\": \"sky\"}]}"
expect_error "--depth $dir/in.ply: is also the input $dir/s_reads.json" render --scene "$dir/s_reads.json" --width 8 --height 8 --out "$dir/s.png" --depth "$dir/in.ply"
cmp -s "$dir/in.ply" "$dir/in.copy" || { echo "FAIL: an input was overwritten"; fails=$((fails + 1)); }
# A cloud a few 1e-38 across: Morton order at load must not convert infinities (UB under UBSan).
printf '0 0 0\n1e-38 0 0\n0 2e-38 0\n3e-39 1e-38 1e-38\n' >"$dir/tiny.xyz"
if "$pcrt" info "$dir/tiny.xyz" >/dev/null 2>"$dir/err"; then echo "ok: pcrt info on a cloud 1e-38 across"; else echo "FAIL: pcrt info on a tiny cloud: $(cat "$dir/err")"; fails=$((fails + 1)); fi
# Sweep and check outputs and inputs of the wrong kind.
config="$(dirname "$0")/../configs/ci.json"
expect_error "--out $dir/keep.png: is a file, not a directory" sweep "$config" --out "$dir/keep.png"
# A shard count past cluster submit's bound is refused, not allocated (1e9) or overflowed (1e30).
expect_error "--shard 0/1e30: n is outside [1, 100000]" sweep "$config" --out "$dir/shard_out" --shard 0/1e30
expect_error "--shard 0/1e9: n is outside [1, 100000]" sweep "$config" --out "$dir/shard_out" --shard 0/1e9
expect_error "--shard 3/3: needs whole numbers 0 <= i < n" sweep "$config" --out "$dir/shard_out" --shard 3/3
expect_error "$dir/statsdir: is a directory, not a file" check --config "$dir/statsdir" --baseline "$dir/b.json"
expect_error "$dir/statsdir: is a directory, not a file" check --config "$config" --baseline "$dir/statsdir"
expect_error "--baseline $dir/statsdir: is a directory" check --config "$config" --baseline "$dir/statsdir" --update
# Names with control characters are printed escaped, on one line.
printf '0 0 0\nnan 1 1\n' >"$dir/new
line.xyz"
expect_error 'new\nline.xyz: line 2' info "$dir/new
line.xyz"
# Unknown command: one line, exit 1 like every other error; no arguments: usage, non-zero.
expect_error "unknown command 'frobnicate'" frobnicate
if "$pcrt" >/dev/null 2>&1; then echo "FAIL: no command exited 0"; fails=$((fails + 1)); fi
[ "$fails" -eq 0 ] && echo "all CLI error paths ok"
exit "$fails"
