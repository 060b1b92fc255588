#!/usr/bin/env python3
"""Writes configs/thesis.json: every claim of the registry that pcrt can judge, sized for power
(harness/fit_test.cpp: on these designs an exactly true claim is called `exceeds` at most 5% of
the time, a violation a class up at least 90%, a between-class one `holds` at most 5%).
Growth designs span 2 decades in N and M and at least 1 in K, k, S, B; op-count experiments run
REPLICATES dataset seeds per grid point, whose scatter is the pure error the claimed model's lack
of fit is tested against. Which methods are real-time, iterative or build over their own items,
and how each method's own claims are swept (MethodInfo::designs, ::real_time_designs), is read
from the registry (`pcrt list --json`: what each method declares), never listed here; every
claim the registry says is tested must be judged by some experiment, or this script fails.
Run it after changing the design or a method's declaration; the config is committed.
Usage: make_thesis_config.py [--pcrt PCRT] [OUT | --check CONFIG]"""
import argparse, json, pathlib, subprocess, sys

ARGS = argparse.ArgumentParser()
ARGS.add_argument("--pcrt", default="build/bin/pcrt")
ARGS.add_argument("--check", help="exit 1 unless CONFIG is what this script writes")
ARGS.add_argument("out", nargs="?", default="configs/thesis.json")
ARGS = ARGS.parse_args()
try:
    CATALOGUE = json.loads(subprocess.run([ARGS.pcrt, "list", "--json"], check=True,
                                          capture_output=True, text=True).stdout)
    METHODS = CATALOGUE["methods"]
except (OSError, subprocess.CalledProcessError) as e:
    sys.exit(f"{ARGS.pcrt}: cannot list the methods ({e}); build pcrt or pass --pcrt")

SCAN = "../data/cgal/points_3/building.ply"  # relative to the config's folder
def geo(lo, hi, n):
    return [int(round(lo * (hi / lo) ** (i / (n - 1)))) for i in range(n)]
N_SPHERE = geo(1000, 128000, 8)
N_SCAN = geo(1000, 100000, 9)  # the whole scan at the top: its replicates are one point there
N_BUILD = geo(2500, 640000, 9)
WORK = "work"
REPLICATES = 3
ITERATIVE = [m["id"] for m in METHODS if m["iterative_claim"]]
REAL_TIME = [m["id"] for m in METHODS if m["real_time_claim"]]
OWN_ITEMS = [m["id"] for m in METHODS if m["own_items"]]

def fit(claim, variable=None, metric=WORK, per=None, **kw):
    f = {"claim": claim, "metric": metric}
    if variable: f["variable"] = variable
    if per: f["per"] = per
    f.update(kw)
    return f

def whole(v):
    return int(v) if isinstance(v, float) and v.is_integer() else v

# What one experiment's designs share (its grid, kind and datasets), and what designs of one claim
# in it share besides.
EXPERIMENT_KEYS = ("structure", "param", "values", "N", "M", "B", "Ns", "build", "fixed", "replicates",
                   "shapes")
AGREE = EXPERIMENT_KEYS + ("variable", "per", "x", "max", "timed", "free")

def group_designs():
    """The methods' designs (MethodInfo::designs) by experiment. Methods naming one experiment
    share its runs: their designs must agree on everything but the counters summed (the union is
    fitted: a method's own counters are zero on the others' runs), and declare the same claims."""
    groups = {}
    for m in METHODS:
        for d in m["designs"]:
            g = groups.setdefault(d["experiment"], {"methods": [], "claims": {}, "by": {}})
            if m["id"] not in g["methods"]:
                g["methods"].append(m["id"])
            g["by"].setdefault(m["id"], set()).add(d["claim"])
            first = g["claims"].setdefault(d["claim"], dict(d, metric=[], first=m["id"]))
            for k in AGREE:
                if first[k] != d[k]:
                    sys.exit(f"{m['id']}: design {d['experiment']}/{d['claim']} has {k} = {d[k]}, "
                             f"{first['first']} declares {first[k]} for the same experiment")
            first["metric"] += [c for c in d["metric"] if c not in first["metric"]]
    for name, g in groups.items():
        designs = list(g["claims"].values())
        for k in EXPERIMENT_KEYS:
            if any(c[k] != designs[0][k] for c in designs):
                sys.exit(f"experiment {name}: its designs disagree on {k}")
        for mid, claims in g["by"].items():
            if claims != set(g["claims"]):
                sys.exit(f"{mid}: experiment {name} judges claims {sorted(g['claims'])}, "
                         f"the method declares {sorted(claims)} in it")
    return groups

def declared_experiments():
    out = []
    for name, g in group_designs().items():
        d = next(iter(g["claims"].values()))
        grid = {"N": d["Ns"] or [d["N"]]}
        if not d["build"]:
            grid.update({"M": [d["M"]], "B": [d["B"]]})
        if d["param"]:
            grid["set." + d["param"]] = d["values"]
        e = {"name": name, "kind": "build" if d["build"] else "render", "methods": g["methods"],
             "datasets": DATA4 if d["shapes"] else ["sphere"], "grid": grid}
        if d["structure"]:
            e["structures"] = [d["structure"]]
        e.update({"set." + k: whole(v) for k, v in d["fixed"].items()})
        if any(c["timed"] for c in g["claims"].values()):
            e["repetitions"] = 5  # a time is the median of 5
        if d["replicates"] != 1:
            e["replicates"] = d["replicates"]
        e["fits"] = [design_fit(claim, c) for claim, c in g["claims"].items()]
        out.append(e)
    return out

def design_fit(claim, c):
    """The fit of one declared design: its counters summed per `per`, or the frame's time."""
    if c["timed"]:
        metric, per = "time", None
    else:
        metric = ["ops_" + x for x in c["metric"]] if len(c["metric"]) > 1 else "ops_" + c["metric"][0]
        per = "ops_" + c["per"]
    return fit("{method}/" + claim, c["variable"] or None, metric, per,
               **({"x": c["x"]} if c["x"] else {}),
               **({"max": whole(c["max"])} if c["max"] else {}),
               **({"free": c["free"]} if c["free"] else {}))

def real_time_experiments():
    """Table 5.1's real-time claims, in the experiments each real-time method declares
    (MethodInfo::real_time_designs): one frame at N points, 512x512, 1 spp, 1 bounce."""
    groups = {}
    for m in METHODS:
        if not m["real_time_claim"]:
            continue
        for r in m["real_time_designs"]:
            g = groups.setdefault(r["experiment"], dict(r, methods=[], first=m["id"]))
            if (g["N"], g["repetitions"], g["why"]) != (r["N"], r["repetitions"], r["why"]):
                sys.exit(f"{m['id']}: real-time experiment {r['experiment']} differs from "
                         f"{g['first']}'s (N, repetitions and description must agree)")
            g["methods"].append(m["id"])
    default = (f"Table 5.1's real-time methods at 10^6 points (Wald and Seidel's own N), "
               f"512x512, 1 spp, 1 bounce")
    return [{"name": name, "kind": "render", "methods": g["methods"], "datasets": ["sphere"],
             "description": g["why"] or default,
             "grid": {"N": [g["N"]], "M": [262144], "B": [1]}, "repetitions": g["repetitions"],
             "fits": [fit("{method}/real_time", None, "fps", min=1)]}
            for name, g in groups.items()]

E = []
for name, ds, ns in [("build_sphere", "sphere", N_BUILD), ("build_scan", SCAN, N_SCAN)]:
    E.append({"name": name, "kind": "build", "methods": ["reference_splat"],
              "structures": ["kd_tree", "octree", "sphere_tree", "bvh", "grid"],
              "datasets": [ds], "grid": {"N": ns}, "repetitions": 5, "replicates": REPLICATES,
              "fits": [fit("{structure}/build", "N", "ops_prep_build_item_visits"),
                       fit("{structure}/build", "N", "time")]})
E.append({"name": "build_own_items", "kind": "build",
          "description": "structures over the methods' own items (implicit cells, patches, fitted and reduced splats)",
          "methods": OWN_ITEMS,
          "datasets": ["sphere"], "grid": {"N": geo(2500, 250000, 7)}, "replicates": REPLICATES,
          "fits": [fit("{method}/build", "N", "ops_prep_build_item_visits")]})
N_QUERY = geo(1000, 512000, 10)  # to 512000: below 10^5 a sphere hierarchy's log N is marginal
for name, ds, ns in [("query_sphere", "sphere", N_QUERY), ("query_scan", SCAN, N_SCAN)]:
    E.append({"name": name, "kind": "render", "methods": ["reference_splat"],
              "structures": ["kd_tree", "octree", "sphere_tree", "bvh", "grid"],
              "datasets": [ds], "grid": {"N": ns, "M": [4096], "B": [0]}, "replicates": REPLICATES,
              "fits": [fit("{structure}/query", "N", "ops_nodes_visited", "ops_rays_cast", free=["K"])]})
# Table 5.4's row without a structure: the brute-force oracle counts no build work (it lists the
# item indices), so its build is judged in time; its query walks every item, so in items per ray.
E.append({"name": "brute_force_build", "kind": "build", "methods": ["reference_splat"],
          "structures": ["brute_force"], "datasets": ["sphere"], "grid": {"N": N_BUILD}, "repetitions": 5,
          "replicates": REPLICATES,
          "fits": [fit("brute_force/build", "N", "time")]})
E.append({"name": "brute_force_query", "kind": "render", "methods": ["reference_splat"],
          "structures": ["brute_force"], "datasets": ["sphere", SCAN],
          "grid": {"N": N_SCAN, "M": [1024], "B": [0]}, "replicates": REPLICATES,
          "fits": [fit("brute_force/query", "N", "ops_items_visited", "ops_rays_cast", free=["K"])]})
E.append({"name": "grid_occupancy", "kind": "render", "methods": ["reference_splat"],
          "structures": ["grid"], "datasets": ["cube", "sphere"],
          "description": "points per visited cell at G = N/c: a volume (the thesis's uniform cloud), and a surface, which the claim's precondition leaves unjudged",
          "grid": {"N": N_SPHERE, "M": [1024], "B": [0]}, "replicates": REPLICATES,
          "fits": [fit("grid/occupancy", "N", "ops_items_visited", "ops_leaves_visited", free=["K"])]})
# From 4000 points: below that the sphere's radius is under about 20 h, its curvature at the leaf
# scale changes the points per leaf, and K would drift with N for reasons that are not N.
N_FRAME = geo(4000, 512000, 8)
for name, ds, ns in [("frame_in_N_sphere", "sphere", N_FRAME), ("frame_in_N_scan", SCAN, N_SCAN)]:
    E.append({"name": name, "kind": "render", "methods": ["surveyed"], "datasets": [ds],
              "grid": {"N": ns, "M": [1024], "B": [1]}, "replicates": REPLICATES,
              # O(SMB(log N + K)) adds K: where the papers' leaf rules move it, it is a covariate.
              "fits": [fit("{method}/frame_reduced", "N", covariate="K"),
                       fit("{method}/requery", "N", "ops_leaves_visited", "ops_rays_cast")]})
E.append({"name": "frame_in_M", "kind": "render", "methods": ["surveyed"], "datasets": ["sphere"],
          "grid": {"N": [10000], "M": [144, 256, 576, 1024, 2304, 4096, 9216, 16384], "B": [1]},
          "replicates": REPLICATES,
          "fits": [fit("{method}/frame_reduced", "M")]})
E.append({"name": "frame_in_S", "kind": "render", "methods": ["surveyed"], "datasets": ["sphere"],
          "grid": {"N": [5000], "M": [256], "S": [1, 2, 3, 4, 6, 8, 12, 16, 24, 32], "B": [1]},
          "replicates": REPLICATES,
          "fits": [fit("{method}/frame", "S")]})
E.append({"name": "frame_in_B", "kind": "render", "methods": ["surveyed"], "datasets": ["sphere"],
          "camera": "inside",
          "description": "camera at the centre of a closed sphere: every bounce hits again",
          "grid": {"N": [5000], "M": [256], "B": [1, 2, 3, 4, 6, 8, 12, 16, 24, 32]},
          "replicates": REPLICATES,
          "fits": [fit("{method}/frame", "B")]})
DATA4 = ["sphere", "torus", "bumpy_sphere", SCAN]
# The frame claims in B again on paths that really bounce (a closed mirror sphere, two facing
# mirrors, glass on a mesh floor): configs/bounces.json's experiments, taken from that file so
# the two configs cannot disagree.
BOUNCES = pathlib.Path(__file__).resolve().parent.parent / "configs/bounces.json"
E.extend(json.load(open(BOUNCES))["experiments"])
E.extend(declared_experiments())
E.append({"name": "mls_iterations", "kind": "render", "methods": ["adamson_alexa_2003", "tejada_2006"],
          "datasets": DATA4, "grid": {"N": [20000], "M": [4096], "B": [1]},
          # The thesis's "2 or 3" sits in Algorithm 3's refinement loop: per intersection run. Per
          # hitting ray, summed over every leaf it visits, is pcrt's own observation.
          "fits": [fit("mls/iterations", None, "ops_mls_fits", "ops_mls_runs", max=3),
                   fit("mls/fits_per_hit", None, "ops_mls_fits", "ops_ray_hits", max=3)]})
E.append({"name": "iterations", "kind": "render", "methods": ITERATIVE, "datasets": DATA4,
          "description": "chapter 6: iterations per iterative run few enough not to matter",
          "grid": {"N": [20000], "M": [4096], "B": [1]},
          "fits": [fit("{method}/iterations", None, "I_run", max=3)]})
E.append({"name": "delaunay_uniform", "kind": "reconstruct", "reconstructions": ["delaunay"],
          "description": "the thesis's precondition: points uniform in a ball",
          "datasets": ["ball"], "grid": {"N": geo(2000, 256000, 8)}, "repetitions": 5,
          "replicates": REPLICATES,
          "fits": [fit("delaunay/uniform", "N", "time"), fit("delaunay/uniform", "N", "ops_predicates")]})
E.append({"name": "delaunay_worst", "kind": "reconstruct", "reconstructions": ["delaunay"],
          "datasets": ["skew_lines"], "grid": {"N": geo(40, 4000, 9)},
          "repetitions": 3, "replicates": REPLICATES,
          "fits": [fit("delaunay/worst", "N", "time"), fit("delaunay/worst", "N", "ops_predicates")]})
E.append({"name": "afsr", "kind": "reconstruct", "reconstructions": ["afsr"], "datasets": ["sphere", SCAN],
          "grid": {"N": N_SCAN}, "repetitions": 3, "replicates": REPLICATES,
          "fits": [fit("afsr/reconstruct", "N", "time")]})
# Chapter 7's comparison is Adamson and Alexa's direct MLS tracing against reconstruction.
E.append({"name": "crossover", "kind": "crossover", "methods": ["adamson_alexa_2003"], "repetitions": 3,
          "datasets": ["sphere"], "grid": {"N": geo(2000, 200000, 9), "M": [65536], "B": [1]},
          "replicates": REPLICATES,
          "fits": [fit("direct/total", "N", ["direct_setup_s", "direct_frame_s"]),
                   fit("reconstruction/total", "N", ["mesh_setup_s", "mesh_frame_s"])]})
E.extend(real_time_experiments())
cfg = {"name": "thesis",
       "description": "Every claim of the registry pcrt can judge (Tables 5.1, 5.4, 5.5, 6.1, sections 5.1.1, 5.4, 5.5.1, 5.5.2, chapters 6 and 7), on a synthetic sphere (and torus, cube, ball) and a real scan (CGAL's building.ply, subsampled). Written by scripts/make_thesis_config.py. Frame claims are judged on each method's declared work, never on rays.",
       "threads": 2, "repetitions": 1, "time_limit_s": 180, "experiments": E}
def judged(experiments):
    """The claim ids the experiments' fits judge, their templates expanded."""
    surveyed = [m["id"] for m in METHODS if m["thesis_ref"] != "-"]
    ids = set()
    for e in experiments:
        methods = surveyed if e.get("methods") == ["surveyed"] else e.get("methods", [])
        for f in e["fits"]:
            ids |= {f["claim"].format(method=m, structure=s)
                    for m in methods or [""] for s in e.get("structures", [""])}
    return ids

# `pcrt calibrate` judges the calibration workloads, and a crossover experiment measures chapter
# 7's crossover frames rather than fitting them; every other tested claim is a sweep's fit.
NOT_SWEPT = {"reconstruction/crossover"} if any(e["kind"] == "crossover" for e in E) else set()
unjudged = sorted(c["id"] for c in CATALOGUE["claims"]
                  if c["tested"] and not c["id"].startswith("calibration/") and c["id"] not in NOT_SWEPT)
unjudged = [c for c in unjudged if c not in judged(E)]
if unjudged:
    sys.exit(f"make_thesis_config.py: no experiment judges the registry's tested claims "
             f"{', '.join(unjudged)}: declare a design for them on their method")
if ARGS.check:
    if json.load(open(ARGS.check)) != cfg:
        print(f"{ARGS.check}: not what scripts/make_thesis_config.py writes from the registry "
              f"(run it to regenerate)", file=sys.stderr)
        sys.exit(1)
else:
    json.dump(cfg, open(ARGS.out, "w"), indent=1)
