#!/usr/bin/env bash
# The scale benchmark (issue 16): each method at each N on a generated sphere, one `pcrt render`
# per run (512x512 primary rays, no bounces, no light) under /usr/bin/time -v. Per run it records
# peak resident memory (bytes per point = peak RSS / N, so the cloud, the method's data, the
# structure and the process's own ~10 MB all count), setup CPU seconds (user + system CPU of the
# process, all threads, when load, prepare and build are done), the phases' wall times and
# primary rays per second, and for the compressed Hubo variants the bytes their compressed data
# holds (prepare counters qkd_bytes, codebook_bytes). One JSON line per run appended to
# OUT/runs.jsonl; OUT/summary.md is regenerated from it. Clouds are generated, never committed.
# Usage: scripts/scale.sh OUT "N ..." "METHOD[@k=v] ..." [build/bin/pcrt]
# (PCRT_DATA=FILE renders that file instead of the generated sphere; give its point count as N.)
# METHOD may name a structure after '/' and carry --set values after '@', comma separated
# (e.g. reference_splat/kd_tree, hubo_2006@quantized=1); a trailing +stream renders with --stream
# (the generator's points straight into the method, never the whole cloud: hubo_2006@quantized=1+stream).
set -euo pipefail
out=$1
sizes=$2
methods=$3
pcrt=${4:-build/bin/pcrt}
threads=${PCRT_THREADS:-2}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for n in $sizes; do
  for spec in $methods; do
    sets=()
    base=$spec
    if [[ $spec == *+stream ]]; then
      sets+=(--stream)
      base=${spec%+stream}
    fi
    m=${base%%@*}
    if [[ $m == */* ]]; then
      sets+=(--structure "${m#*/}")
      m=${m%%/*}
    fi
    if [[ $base == *@* ]]; then
      IFS=',' read -ra kv <<<"${base#*@}"
      for x in "${kv[@]}"; do sets+=(--set "$x"); done
    fi
    data=${PCRT_DATA:-sphere:n=$n,seed=1}  # PCRT_DATA: a file of N points instead
    set +e
    /usr/bin/time -v -o "$tmp/time" "$pcrt" render --method "$m" "${sets[@]}" --data "$data" \
      --out "$tmp/frame.png" --width 512 --height 512 --bounces 0 --no-light \
      --threads "$threads" --stats "$tmp/stats.json" >/dev/null 2>"$tmp/err"
    rc=$?
    set -e
    /usr/bin/python3 - "$tmp" "$spec" "$n" "$rc" "$threads" "$(git rev-parse --short HEAD)" "$data" \
      >>"$out/runs.jsonl" <<'PY'
import json, re, sys
from pathlib import Path
tmp, spec, n, rc, threads, commit, data = Path(sys.argv[1]), sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6], sys.argv[7]
t = (tmp / "time").read_text()
def field(name):
    m = re.search(re.escape(name) + r":\s*([0-9.:]+)", t)
    return m.group(1) if m else None
rss_kb = int(field("Maximum resident set size (kbytes)"))
cpu = float(field("User time (seconds)")) + float(field("System time (seconds)"))
row = {"method": spec, "N": n, "exit": rc, "commit": commit, "threads": threads,
       "peak_rss_bytes": rss_kb * 1024, "bytes_per_point": rss_kb * 1024 / n, "cpu_seconds": cpu,
       "wall_seconds": field("Elapsed (wall clock) time (h:mm:ss or m:ss)"), "dataset": data}
if rc == 0:
    s = json.loads((tmp / "stats.json").read_text())
    tm = s["timings"]
    render = tm.get("render", 0.0)
    row["timings"] = tm
    row["setup_cpu_seconds"] = s["process"]["setup_cpu_seconds"]
    if "estimated_scene_bytes" in s["process"]:
        row["estimated_scene_bytes"] = s["process"]["estimated_scene_bytes"]
    row["structure_bytes"] = s.get("structure_bytes")
    # What a compressed variant holds (hubo_2006 quantized=1, hubo_2007 compressed=1).
    for k in ("qkd_bytes", "codebook_bytes"):
        if k in s.get("prepare_counters", {}):
            row["compressed_bytes"] = s["prepare_counters"][k]
    rays = s["counters"].get("rays_cast", 0)
    row["primary_rays_per_second"] = rays / render if render > 0 else None
else:
    row["error"] = (tmp / "err").read_text().strip().splitlines()[-1:]
print(json.dumps(row))
PY
    tail -1 "$out/runs.jsonl"
  done
done
/usr/bin/python3 - "$out" <<'PY'
import json, sys
from pathlib import Path
out = Path(sys.argv[1])
rows = [json.loads(l) for l in (out / "runs.jsonl").read_text().splitlines() if l.strip()]
lines = ["| method | N | commit | peak RSS (MiB) | bytes/point | estimate (B/point, + cloud) | compressed B/point | setup CPU-s | setup wall s | primary Mrays/s | exit |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    tm = r.get("timings", {})
    wall = sum(v for k, v in tm.items() if k in ("load", "prepare", "build"))
    rps = r.get("primary_rays_per_second")
    cloud = 0 if r["method"].endswith("+stream") else 24  # a streamed cloud is never held
    est = f"{r['estimated_scene_bytes'] / r['N'] + cloud:.0f}" if "estimated_scene_bytes" in r else "-"
    comp = f"{r['compressed_bytes'] / r['N']:.1f}" if "compressed_bytes" in r else "-"
    lines.append(f"| {r['method']} | {r['N']:.0e} | {r['commit']} | {r['peak_rss_bytes']/2**20:.0f} | "
                 f"{r['bytes_per_point']:.1f} | {est} | {comp} | {r.get('setup_cpu_seconds', float('nan')):.1f} | {wall:.1f} | "
                 f"{(rps or 0)/1e6:.2f} | {r['exit']} |")
(out / "summary.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
PY
