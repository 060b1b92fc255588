"""The Python module against the command line: the same hits, counters and errors on the same
input, zero-copy views, thread-count independence, the registry and sweep reading."""
import csv
import json
import os
import subprocess
import signal
import threading
import time

import numpy as np
import pytest

import pcrt

EXE = os.environ["PCRT_EXE"]


def sphere_rays(n, seed=1):
    """Rays from a shell of radius 3 towards jittered points near the unit sphere's centre."""
    rng = np.random.default_rng(seed)
    o = rng.normal(size=(n, 3))
    o = 3 * o / np.linalg.norm(o, axis=1, keepdims=True)
    d = rng.normal(scale=0.4, size=(n, 3)) - o
    return o.astype(np.float32), d.astype(np.float32)


def cli_trace(tmp_path, data, method, structure, o, d):
    rays = tmp_path / "rays.csv"
    with open(rays, "w") as f:
        f.write("ox,oy,oz,dx,dy,dz\n")
        for a, b in zip(o, d):
            f.write(",".join(f"{v:.9g}" for v in (*a, *b)) + "\n")
    hits, stats = tmp_path / "hits.csv", tmp_path / "stats.json"
    subprocess.run([EXE, "trace", "--method", method, "--structure", structure, "--data", data,
                    "--rays", str(rays), "--out", str(hits), "--stats", str(stats)],
                   check=True, capture_output=True)
    with open(hits) as f:
        rows = list(csv.DictReader(f))
    return rows, json.load(open(stats))


def test_load_gives_read_only_views_without_copies():
    cloud = pcrt.load("sphere:n=2000,seed=3")
    assert len(cloud) == 2000 and cloud.name == "sphere:n=2000,seed=3"
    p = cloud.positions
    assert p.shape == (2000, 3) and p.dtype == np.float32
    assert np.shares_memory(p, cloud.positions)  # both views of the cloud's own array
    assert np.allclose(np.linalg.norm(p, axis=1), 1, atol=1e-5)
    assert np.allclose(np.linalg.norm(cloud.normals, axis=1), 1, atol=1e-5)
    with pytest.raises(ValueError):
        p[0, 0] = 5
    del cloud  # the view keeps the cloud alive
    assert np.isfinite(p).all() and p.shape == (2000, 3)


def test_a_georeferenced_file_is_held_relative_to_its_origin(tmp_path):
    path = tmp_path / "tile.xyz"
    path.write_text("".join(f"{600000.125 + 0.5 * i} {240000.25 + 0.25 * i} 80.25\n"
                            for i in range(50)))
    cloud = pcrt.load(str(path))
    assert cloud.origin == (600000.0, 240000.0, 80.0)
    world = np.asarray(cloud.positions, dtype=np.float64) + np.array(cloud.origin)
    assert np.abs(world[:, 2] - 80.25).max() == 0  # exact: local values a float holds
    assert np.abs(world[:, 0] - 600000).max() < 30 and np.abs(cloud.positions).max() < 30
    assert pcrt.load("sphere:n=100").origin == (0.0, 0.0, 0.0)


def test_from_arrays_validates_like_a_file():
    cloud = pcrt.load("sphere:n=500")
    copy = pcrt.from_arrays(cloud.positions, normals=cloud.normals, name="mine")
    assert np.array_equal(copy.positions, cloud.positions) and copy.name == "mine"
    twice = pcrt.from_arrays(np.concatenate([cloud.positions, cloud.positions[:10]]), name="twice")
    assert len(twice) == 500  # exact duplicates dropped, as a file's are
    bad = np.array(cloud.positions)
    bad[7, 1] = np.nan
    with pytest.raises(pcrt.Error, match="mine"):
        pcrt.from_arrays(bad, name="mine")
    with pytest.raises(pcrt.Error, match="positions: expected an array of shape"):
        pcrt.from_arrays(np.zeros((4, 2)))


@pytest.mark.parametrize("method,structure", [("reference_splat", "kd_tree"),
                                              ("goradia_2010", "octree")])
def test_trace_matches_the_command_line(tmp_path, method, structure):
    data = "sphere:n=20000,seed=2,noise=0.001"
    o, d = sphere_rays(3000)
    rows, stats = cli_trace(tmp_path, data, method, structure, o, d)
    scene = pcrt.Scene(pcrt.load(data), method=method, structure=structure)
    hits = scene.trace(o, d)
    cli_hit = np.array([r["hit"] == "1" for r in rows])
    assert np.array_equal(hits["hit"], cli_hit) and 0.3 < cli_hit.mean() < 1
    t = np.array([float(r["t"]) if r["hit"] == "1" else np.inf for r in rows], dtype=np.float32)
    assert np.array_equal(hits["t"], t)
    p = np.array([[float(r[k]) for k in ("px", "py", "pz")] for r in rows if r["hit"] == "1"],
                 dtype=np.float32)
    assert np.array_equal(hits["position"][cli_hit], p)
    assert (hits["primitive"][~cli_hit] == -1).all() and (hits["primitive"][cli_hit] >= 0).all()
    assert scene.counters == stats["counters"]
    assert scene.prepare_counters == stats["prepare_counters"]


def test_counters_do_not_depend_on_threads():
    scene = pcrt.Scene(pcrt.load("sphere:n=5000"), method="hubo_2006")
    o, d = sphere_rays(2000, seed=5)
    one = scene.trace(o, d, threads=1)
    c1 = scene.counters
    two = scene.trace(o, d, threads=2)
    assert scene.counters == c1 and c1["rays_cast"] == 2000
    assert np.array_equal(one["t"], two["t"])


def test_trace_runs_beside_python_threads():
    scene = pcrt.Scene(pcrt.load("sphere:n=5000"), method="reference_splat")
    o, d = sphere_rays(4000)
    results = []
    threads = [threading.Thread(target=lambda: results.append(scene.trace(o, d)["t"]))
               for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 2 and np.array_equal(results[0], results[1])


def test_concurrent_calls_keep_their_own_thread_counts():
    # Each call runs in an arena of its own: one at 1 thread and one at 2 at the same time give
    # the hits and counters of either alone, and TBB prints no warning about a process limit.
    scene = pcrt.Scene(pcrt.load("sphere:n=5000"), method="reference_splat")
    o, d = sphere_rays(4000)
    alone = scene.trace(o, d, threads=1)["t"]
    results = {}

    def trace(n):
        results[n] = scene.trace(o, d, threads=n)["t"]

    threads = [threading.Thread(target=trace, args=(n,)) for n in (1, 2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert np.array_equal(results[1], alone) and np.array_equal(results[2], alone)
    with pytest.raises(pcrt.Error, match="threads = 5000 is impossible"):
        scene.trace(o, d, threads=5000)


def test_frames_keep_to_the_command_lines_limits():
    scene = pcrt.Scene(pcrt.load("sphere:n=500"), method="reference_splat")
    with pytest.raises(pcrt.Error, match=r"spp = 2147483647: must lie in \[1, 65536\]"):
        scene.render(width=8, height=8, spp=2**31 - 1)
    with pytest.raises(pcrt.Error, match=r"bounces = 65: must lie in \[0, 64\]"):
        scene.render(width=8, height=8, bounces=65)
    with pytest.raises(pcrt.Error, match="width 16385"):
        scene.render(width=16385, height=8)


def test_render_matches_the_command_line_counters(tmp_path):
    data = "sphere:n=5000"
    scene = pcrt.Scene(pcrt.load(data), method="reference_splat")
    image = scene.render(width=40, height=30, spp=2, bounces=1)
    assert image.shape == (30, 40, 3) and image.dtype == np.float32
    assert np.isfinite(image).all() and (image >= 0).all() and image.max() > 0
    stats = tmp_path / "s.json"
    subprocess.run([EXE, "render", "--method", "reference_splat", "--data", data, "--width", "40",
                    "--height", "30", "--spp", "2", "--bounces", "1", "--out",
                    str(tmp_path / "f.png"), "--stats", str(stats)], check=True,
                   capture_output=True)
    assert scene.counters == json.load(open(stats))["counters"]
    assert scene.counters["primary_rays"] == 40 * 30 * 2


def test_errors_are_the_command_lines_one_line_errors():
    cloud = pcrt.load("sphere:n=500")
    with pytest.raises(pcrt.Error, match="unknown method 'nope'"):
        pcrt.Scene(cloud, method="nope")
    with pytest.raises(pcrt.Error, match="^Scene keyword leaf_siz: not a parameter"):
        pcrt.Scene(cloud, method="reference_splat", leaf_siz=4)
    with pytest.raises(pcrt.Error, match="parameter leaf_size: expected a number, got big"):
        pcrt.Scene(cloud, method="reference_splat", structure="kd_tree", leaf_size="big")
    with pytest.raises(pcrt.Error, match="no such file"):
        pcrt.load("/nonexistent/cloud.ply")
    scene = pcrt.Scene(cloud, method="reference_splat")
    o, d = sphere_rays(3)
    d[1] = 0
    with pytest.raises(pcrt.Error, match="ray 1: zero direction"):
        scene.trace(o, d)
    with pytest.raises(pcrt.Error, match="origins has 3 rows but directions 2"):
        scene.trace(o, d[:2])
    proc = subprocess.run([EXE, "render", "--method", "nope", "--data", "sphere:n=500", "--out",
                           "/tmp/never.png"], capture_output=True, text=True)
    assert "unknown method 'nope'" in proc.stderr and proc.returncode == 1


def test_methods_and_structures_come_from_the_registry():
    listed = json.loads(subprocess.run([EXE, "list", "--json"], check=True, capture_output=True,
                                       text=True).stdout)
    methods = pcrt.methods()
    assert methods == listed["methods"]  # one serialisation: the same keys and values
    assert pcrt.structures() == listed["structures"]
    assert sum(m["thesis_ref"] != "-" for m in methods) == 16
    for m in methods:
        for p in m["parameters"]:
            assert p["min"] <= p["default"] <= p["max"], (m["id"], p)
    assert {"kd_tree", "octree", "grid"} <= {s["id"] for s in pcrt.structures()}


def test_read_sweep(tmp_path):
    config = tmp_path / "c.json"
    config.write_text(json.dumps({"name": "py", "experiments": [
        {"name": "e", "kind": "build", "datasets": ["sphere"], "grid": {"N": [1000, 2000, 4000]}}]}))
    subprocess.run([EXE, "sweep", str(config), "--out", str(tmp_path / "s")], check=True,
                   capture_output=True)
    runs = pcrt.read_sweep(str(tmp_path / "s"))
    try:
        import pandas
        assert isinstance(runs, pandas.DataFrame) and list(runs["N"]) == [1000, 2000, 4000]
    except ImportError:
        assert [int(r["N"]) for r in runs] == [1000, 2000, 4000]
    with pytest.raises(pcrt.Error, match="a sweep directory"):
        pcrt.read_sweep(str(tmp_path))


@pytest.mark.parametrize("content", [b"", b"N,M\n1,2\n3,4,5,6\n", b"N,M\n\xff\xfe1,2\n",
                                     b'N,M\n"1,2\n'])
def test_read_sweep_of_a_damaged_runs_csv_is_an_error_naming_it(tmp_path, content):
    (tmp_path / "runs.csv").write_bytes(content)
    with pytest.raises(pcrt.Error, match="runs.csv: .*not a runs.csv pcrt wrote"):
        pcrt.read_sweep(str(tmp_path))


ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


@pytest.mark.parametrize("doc", ["README.md", "docs/python.md", "the module's docstring"])
def test_the_documented_scene_example_runs(doc):
    """The example's Scene line, as written, on a small cloud: its keywords are parameters."""
    text = pcrt.__doc__ if doc.startswith("the") else open(os.path.join(ROOT, doc)).read()
    lines = [l.split("#")[0].strip() for l in text.splitlines() if "scene = pcrt.Scene(" in l]
    assert lines, doc
    for line in lines:
        names = {"pcrt": pcrt, "cloud": pcrt.load("sphere:n=2000")}
        exec(line, names)
        assert names["scene"].render(width=8, height=8).shape == (8, 8, 3)


def test_half_made_objects_raise_instead_of_crashing():
    with pytest.raises(pcrt.Error, match="cloud is None"):
        pcrt.Scene(None, method="reference_splat")
    half = pcrt.Scene.__new__(pcrt.Scene)
    with pytest.raises(TypeError, match="not initialised"):
        half.method
    with pytest.raises(TypeError, match="not initialised"):
        half.render(width=4, height=4)


def interrupted_after(seconds, call):
    """Sends this process SIGINT `seconds` into `call` (Ctrl-C); returns how long after the signal
    the KeyboardInterrupt arrived, or fails if the call returned without one."""
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        call()
    except KeyboardInterrupt:
        return time.monotonic() - start - seconds
    finally:
        timer.cancel()
    pytest.fail(f"the call ended without the interrupt ({time.monotonic() - start:.1f} s)")


def test_ctrl_c_interrupts_a_trace_and_a_frame_within_a_second():
    # Uninterrupted, the trace takes about 150 s here and the frame about half an hour.
    scene = pcrt.Scene(pcrt.load("sphere:n=20000"), method="adamson_alexa_2003")
    n = 4_000_000
    rng = np.random.default_rng(3)
    origins = np.tile(np.array([[0.0, -4.0, 0.0]], np.float32), (n, 1))
    targets = rng.uniform(-1, 1, (n, 3)).astype(np.float32)
    late = interrupted_after(1.0, lambda: scene.trace(origins, targets - origins, threads=2))
    assert late < 1.0, f"the trace stopped {late:.2f} s after Ctrl-C"
    late = interrupted_after(1.0, lambda: scene.render(width=2048, height=2048, spp=64, threads=2))
    assert late < 1.0, f"the frame stopped {late:.2f} s after Ctrl-C"
    # The scene is still usable afterwards.
    assert scene.render(width=8, height=8).shape == (8, 8, 3)


def test_too_many_rays_are_a_memory_error_not_a_shape_error():
    row = np.zeros((1, 3), np.float32)
    huge = np.broadcast_to(row, (10**11, 3))  # no memory of its own
    scene = pcrt.Scene(pcrt.load("sphere:n=500"), method="reference_splat")
    with pytest.raises(pcrt.Error, match="out of memory: a trace of 100000000000 rays"):
        scene.trace(huge, huge)
    with pytest.raises(pcrt.Error, match=r"origins: expected an array of shape \(n, 3\)"):
        scene.trace(np.zeros((4, 2), np.float32), np.zeros((4, 3), np.float32))


def test_a_nul_in_a_text_argument_is_refused_whole():
    with pytest.raises(pcrt.Error, match=r"data: contains a NUL byte at position 12: 'sphere:n=100\\x00,seed=2'"):
        pcrt.load("sphere:n=100\0,seed=2")
    cloud = pcrt.load("sphere:n=100")
    with pytest.raises(pcrt.Error, match=r"method: contains a NUL byte at position 9"):
        pcrt.Scene(cloud, method="reference\0_splat")


def test_read_exr_gives_the_frame_the_command_line_wrote(tmp_path):
    data = "sphere:n=2000,seed=3"
    frame, depth = tmp_path / "f.exr", tmp_path / "d.exr"
    subprocess.run([EXE, "render", "--method", "reference_splat", "--data", data, "--width", "24",
                    "--height", "16", "--out", str(frame), "--depth", str(depth)], check=True,
                   stdout=subprocess.DEVNULL)
    rgb = pcrt.read_exr(str(frame))
    assert sorted(rgb) == ["B", "G", "R"] and rgb["R"].shape == (16, 24)
    direct = pcrt.Scene(pcrt.load(data), "reference_splat").render(width=24, height=16)
    assert np.array_equal(np.stack([rgb[c] for c in "RGB"], axis=-1), direct)
    z = pcrt.read_exr(str(depth))["Z"]
    assert np.isinf(z).any() and np.isfinite(z).any()
    (tmp_path / "cut.exr").write_bytes(frame.read_bytes()[:50])
    with pytest.raises(pcrt.Error, match="cut.exr"):
        pcrt.read_exr(str(tmp_path / "cut.exr"))


def tiled_exr(path, width, height, tile, header_only=False):
    """An uncompressed tiled EXR of one float channel R = 100 y + x, written by hand: tiles at the
    right and bottom edges are cut to the image, as OpenEXR writes them. `header_only`: the header
    and 64 zero bytes, as a cut or forged file."""
    import struct

    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data
    header = b"\x76\x2f\x31\x01" + struct.pack("<I", 2 | 0x200)
    header += attr("channels", "chlist", b"R\0" + struct.pack("<iB3xii", 2, 0, 1, 1) + b"\0")
    header += attr("compression", "compression", b"\0")
    box = struct.pack("<4i", 0, 0, width - 1, height - 1)
    header += attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box)
    header += attr("lineOrder", "lineOrder", b"\0") + attr("pixelAspectRatio", "float", struct.pack("<f", 1))
    header += attr("screenWindowCenter", "v2f", struct.pack("<2f", 0, 0))
    header += attr("screenWindowWidth", "float", struct.pack("<f", 1))
    header += attr("tiles", "tiledesc", struct.pack("<IIB", tile, tile, 0)) + b"\0"
    if header_only:
        path.write_bytes(header + bytes(64))
        return
    chunks = []
    for ty in range(-(-height // tile)):
        for tx in range(-(-width // tile)):
            w, h = min(tile, width - tx * tile), min(tile, height - ty * tile)
            data = b"".join(struct.pack("<f", (ty * tile + y) * 100 + tx * tile + x)
                            for y in range(h) for x in range(w))
            chunks.append(struct.pack("<5i", tx, ty, 0, 0, len(data)) + data)
    offset, table, body = len(header) + 8 * len(chunks), b"", b""
    for c in chunks:
        table += struct.pack("<Q", offset + len(body))
        body += c
    path.write_bytes(header + table + body)


@pytest.mark.parametrize("width,height", [(8, 8), (5, 3), (6, 6)])
def test_a_tiled_exr_reads_its_edge_tiles_in_place(tmp_path, width, height):
    path = tmp_path / "tiled.exr"
    tiled_exr(path, width, height, 4)
    want = np.add.outer(100 * np.arange(height), np.arange(width)).astype(np.float32)
    assert np.array_equal(pcrt.read_exr(str(path))["R"], want)


def test_an_exr_header_promising_more_than_its_file_or_memory_is_refused(tmp_path):
    # Before: tinyexr allocated for the header's promise and the process was killed for memory.
    path = tmp_path / "forged.exr"
    tiled_exr(path, 100000, 100000, 1, header_only=True)
    with pytest.raises(pcrt.Error, match="forged.exr: truncated EXR file: its header promises "
                                         "10000000000 chunks"):
        pcrt.read_exr(str(path))
    tiled_exr(path, 400000, 400000, 400000, header_only=True)
    with pytest.raises(pcrt.Error, match=r"out of memory: .*forged.exr \(400000x400000 pixels"):
        pcrt.read_exr(str(path))


def test_hostile_arrays_and_objects_are_errors():
    c = pcrt.Cloud.__new__(pcrt.Cloud)  # no C++ cloud behind it
    for use in (len, repr, lambda c: c.positions, lambda c: c.bounds, lambda c: c.name):
        with pytest.raises(TypeError, match="pcrt.Cloud is not initialised"):
            use(c)
    p = np.random.default_rng(1).random((10, 3))
    with pytest.raises(pcrt.Error, match="radii: 0 rows for 10 points"):
        pcrt.from_arrays(p, radii=np.ones(0))
    with pytest.raises(pcrt.Error, match="normals: 0 rows for 10 points"):
        pcrt.from_arrays(p, normals=np.zeros((0, 3)))
    with pytest.raises(pcrt.Error, match=r"positions: an array of <U1 values, not numbers"):
        pcrt.from_arrays(np.array([["a", "b", "c"]]))
    with pytest.raises(pcrt.Error, match=r"got shape \(5, 4\)"):
        pcrt.from_arrays(np.zeros((5, 4)))
    with pytest.raises(pcrt.Error, match="from a stream without a size"):
        pcrt.read_exr("/dev/zero")
