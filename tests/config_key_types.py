#!/usr/bin/env python3
"""Every key of the committed sweep configs, given a value of each wrong JSON type, is refused by
`pcrt cluster submit --dry-run` (which reads, expands and plans a config as a sweep does) with one
line naming the config, or accepted; never with nlohmann's own type_error, which names no key and
which only load_sweep_config's last-resort catch turns into an error (the config fuzzer's first
finding was one: "per": {}). Each key path is tried once, in the first experiment that has it,
with the config cut to that experiment so that a run takes a fraction of a second.
Usage: config_key_types.py PCRT CONFIG..."""
import copy, json, os, subprocess, sys, tempfile

pcrt, configs = sys.argv[1], sys.argv[2:]
WRONG = [{}, [], "x", 1.5, -3, None, True, [[1]], {"a": {}}]


def paths(value, at=()):
    """Every key path below `value`, as tuples of keys and list indices."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield at + (k,)
            yield from paths(v, at + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from paths(v, at + (i,))


def shape(path):
    return tuple("*" if isinstance(p, int) else p for p in path)


def cut(config, path):
    """The config with only the experiment `path` is in (or the first, for a top-level key)."""
    c = copy.deepcopy(config)
    e = path[1] if path[0] == "experiments" and len(path) > 1 else 0
    c["experiments"] = [c["experiments"][e]]
    return c, (("experiments", 0) + path[2:]) if path[0] == "experiments" and len(path) > 1 else path


def put(config, path, value):
    target = config
    for p in path[:-1]:
        target = target[p]
    target[path[-1]] = value


failures, tried = [], 0
with tempfile.TemporaryDirectory() as tmp:
    for name in configs:
        original = json.load(open(name))
        folder = os.path.dirname(os.path.abspath(name))
        seen = set()
        for path in paths(original):
            if shape(path) in seen or path == ("experiments",):
                continue
            seen.add(shape(path))
            base, where = cut(original, path)
            base["dataset_dir"] = os.path.join(folder, original.get("dataset_dir", ""))
            for wrong in WRONG:
                c = copy.deepcopy(base)
                put(c, where, wrong)
                file = os.path.join(tmp, "mutated.json")
                json.dump(c, open(file, "w"))
                r = subprocess.run([pcrt, "cluster", "submit", file, "--out", f"{tmp}/out",
                                    "--shards", "1", "--dry-run"], capture_output=True, text=True,
                                   stdin=subprocess.DEVNULL, timeout=60)
                subprocess.run(["rm", "-rf", f"{tmp}/out"], check=True)
                tried += 1
                lines = r.stderr.strip().splitlines()
                bad = (r.returncode not in (0, 1) or "json.exception" in r.stderr or
                       (r.returncode == 1 and (len(lines) != 1 or file not in lines[0])))
                if bad:
                    failures.append(f"{name}: {'.'.join(map(str, path))} = {json.dumps(wrong)}: "
                                    f"exit {r.returncode}: {r.stderr.strip()[:300]}")
for f in failures[:20]:
    print(f, file=sys.stderr)
if failures:
    sys.exit(f"config_key_types.py: {len(failures)} of {tried} wrong-typed keys not refused cleanly")
print(f"config_key_types.py: {tried} wrong-typed keys of {len(configs)} configs, each refused "
      f"or accepted cleanly")
