#!/usr/bin/env bash
# Issue 29, finding 2: a newline in the config's name, in --out, --partition or --sbatch-arg
# became shell lines of the generated shard.sbatch and merge.sbatch. Every value is now either
# checked (the name, a partition: one line naming the field, exit 1, nothing written) or one word:
# single-quoted in the shell lines, and in the #SBATCH lines (which sbatch reads itself) quoted
# the way sbatch reads them, with a control character refused. Hostile paths (spaces, quotes,
# $(touch X), backticks, # and %) for the binary, --out, the current directory and an sbatch
# argument go through `pcrt cluster submit --dry-run`; the scripts then run under bash and the
# printed sbatch commands are run with a fake sbatch. No injected command may run (no file X
# appears), and every path must arrive whole, as one argument.
set -euo pipefail
pcrt=$(realpath "$1")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir"  # an injected `touch X` would land here (or under the current directory of pcrt)
fail() {
  echo "FAIL: $*"
  exit 1
}
no_marker() {
  local found
  found=$(find "$dir" -name X)
  [ -z "$found" ] || fail "$1: an injected command ran: $found"
}

hostile="sp ace 'q' \"dq\" \$(touch X) \`touch X\` #h %p"
mkdir -p "$dir/$hostile/bin" "$dir/$hostile/cwd"
exe="$dir/$hostile/bin/pcrt"
cp "$pcrt" "$exe"  # the scripts call the binary that wrote them (/proc/self/exe)
out="$dir/$hostile/out"
cwd="$dir/$hostile/cwd"
comment="--comment=it's \$(touch X) \`touch X\` #not a comment; \\ too"
cat >"$dir/c.json" <<'JSON'
{"name": "inj", "threads": 1, "experiments": [
  {"name": "b", "kind": "build", "methods": ["reference_splat"], "structures": ["kd_tree"],
   "datasets": ["sphere"], "grid": {"N": [500, 1000, 2000]}}]}
JSON
(cd "$cwd" && "$exe" cluster submit "$dir/c.json" --out "$out" --shards 2 --dry-run \
  --time 0:10:00 --mem 1G "--sbatch-arg=$comment") >"$dir/dry.txt"
no_marker "submit --dry-run"

# 1. The #SBATCH lines, read as sbatch 22.05 reads them (src/sbatch/opt.c, _get_argument:
#    blanks split, '...' and "..." quote, \ escapes, an unquoted # ends the line): one word each,
#    and the paths whole ('%' doubled in --output, where Slurm expands %-patterns).
/usr/bin/python3 - "$out/slurm" "$out" "$cwd" "$comment" <<'PY'
import sys
slurm, out, cwd, comment = sys.argv[1:]

def sbatch_words(text):
    words, i, n = [], 0, len(text)
    while True:
        while i < n and text[i].isspace():
            i += 1
        word, quote, escape = "", None, False
        while i < n and (quote or not text[i].isspace()):
            c = text[i]
            i += 1
            if escape:
                escape = False
            elif c == "\\":
                escape = True
                continue
            elif quote:
                if c == quote:
                    quote = None
                    continue
            elif c in "'\"":
                quote = c
                continue
            elif c == "#":
                return words + [word] if word else words
            word += c
        assert quote is None, f"unmatched {quote} in {text!r}"
        if not word:
            return words
        words.append(word)

for script, log in (("shard.sbatch", "/slurm/logs/shard-%a.log"), ("merge.sbatch", "/slurm/logs/merge.log")):
    words = []
    for line in open(f"{slurm}/{script}").read().split("\n")[1:]:
        if not line.startswith("#"):
            break  # sbatch stops at the first command
        if line.startswith("#SBATCH"):
            w = sbatch_words(line[len("#SBATCH"):])
            assert len(w) == 1, f"{script}: {line!r} is {len(w)} words: {w}"
            words += w
    for want in ("--output=" + out.replace("%", "%%") + log, "--chdir=" + cwd, comment, "--time=0:10:00"):
        assert want in words, f"{script}: {want!r} not among {words}"
print("sbatch reads every #SBATCH line as one whole word")
PY

# 2. The scripts under bash, as Slurm would run them: the shards, then merge, fit and report.
for i in 0 1; do
  SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_JOB_ID=7 bash "$out/slurm/shard.sbatch" >"$dir/shard$i.log" 2>&1 ||
    fail "shard.sbatch $i: $(cat "$dir/shard$i.log")"
done
SLURM_JOB_ID=8 bash "$out/slurm/merge.sbatch" >"$dir/merge.log" 2>&1 || fail "merge.sbatch: $(cat "$dir/merge.log")"
no_marker "the scripts under bash"
test "$(cat "$out/shards/0/runs.jsonl" "$out/shards/1/runs.jsonl" | wc -l)" = 3 || fail "the shards did not run into --out"
test "$(wc -l <"$out/runs.jsonl")" = 3 && test -s "$out/report.md" || fail "merge, fit, report did not land in --out"

# 3. The printed sbatch commands, pasted into a shell with a fake sbatch: each argument whole.
mkdir "$dir/fake"
cat >"$dir/fake/sbatch" <<'SH'
#!/bin/bash
n=$(find "$FAKE_ARGS" -name 'argv.*' | wc -l)
printf '%s\0' "$@" >"$FAKE_ARGS/argv.$n"
echo $((100 + n))
SH
chmod +x "$dir/fake/sbatch"
export FAKE_ARGS=$dir/args
mkdir "$FAKE_ARGS"
grep -c '^would run: sbatch ' "$dir/dry.txt" | grep -qx 2 || fail "dry run printed: $(cat "$dir/dry.txt")"
while IFS= read -r line; do
  PATH=$dir/fake:$PATH eval "${line#would run: }" >/dev/null
done < <(grep '^would run: ' "$dir/dry.txt")
no_marker "the printed sbatch commands"
# The last argument of each is its script, whole.
/usr/bin/python3 - "$FAKE_ARGS" "$out/slurm" <<'PY'
import sys
args, slurm = sys.argv[1:]
calls = [open(f"{args}/argv.{i}", "rb").read().decode().split("\0")[:-1] for i in range(2)]
assert calls[0][-1] == slurm + "/shard.sbatch" and calls[0][1] == "--array=0-1", calls[0]
assert calls[1][-1] == slurm + "/merge.sbatch", calls[1]
PY

# 4. A real submission (fake sbatch on PATH): pcrt calls sbatch without a shell.
rm -f "$FAKE_ARGS"/argv.*
(cd "$cwd" && PATH=$dir/fake:$PATH "$exe" cluster submit "$dir/c.json" --out "$out.2" --shards 2) >/dev/null
tr '\0' '\n' <"$FAKE_ARGS/argv.0" | grep -qxF "$out.2/slurm/shard.sbatch" || fail "sbatch got: $(tr '\0' ' ' <"$FAKE_ARGS/argv.0")"
tr '\0' '\n' <"$FAKE_ARGS/argv.1" | grep -qxF -- "--dependency=afterok:100" || fail "the merge does not depend on the array"
grep -q '"array_job": "100"' "$out.2/slurm/jobs.json" || fail "jobs.json: $(cat "$out.2/slurm/jobs.json")"
no_marker "a submission"

# 5. What no script can hold is refused: one line naming the field, exit 1, nothing written.
refused() {
  local want=$1 where=$2; shift 2
  set +e
  (cd "$where" && "$pcrt" "$@" >/dev/null 2>"$dir/err")
  local rc=$?
  set -e
  [ $rc = 1 ] || fail "pcrt $*: exit $rc, not 1: $(cat "$dir/err")"
  [ "$(wc -l <"$dir/err")" = 1 ] || fail "pcrt $*: not one line: $(cat "$dir/err")"
  grep -qF -- "$want" "$dir/err" || fail "pcrt $*: does not name $want: $(cat "$dir/err")"
  [ ! -e "$dir/r/slurm" ] || fail "pcrt $*: wrote $dir/r/slurm"
  no_marker "pcrt $*"
  echo "ok: $(cat "$dir/err")"
}
nl=$'\n'
submit=(cluster submit "$dir/c.json" --out "$dir/r" --shards 2 --dry-run)
for name in "inj${nl}touch X #" "inj${nl}touch X" "inj \$(touch X)" "inj\`touch X\`" "in j" "inj;touch X" ""; do
  /usr/bin/python3 -c 'import json, sys; c = json.load(open(sys.argv[1])); c["name"] = sys.argv[2]; json.dump(c, open(sys.argv[3], "w"))' \
    "$dir/c.json" "$name" "$dir/named.json"
  refused "name '" "$dir" cluster submit "$dir/named.json" --out "$dir/r" --shards 2 --dry-run
done
for partition in "p${nl}touch X" "p \$(touch X)" "p\`touch X\`" "a b" "p'q" ""; do
  refused "--partition" "$dir" "${submit[@]}" --partition "$partition"
done
refused "--sbatch-arg" "$dir" "${submit[@]}" "--sbatch-arg=--qos=long${nl}touch X"
refused "--time" "$dir" "${submit[@]}" --time "1:00${nl}touch X"
refused "--mem" "$dir" "${submit[@]}" --mem "1G${nl}touch X"
refused "--cpus-per-task" "$dir" "${submit[@]}" --cpus-per-task "1${nl}touch X"
refused "--out" "$dir" cluster submit "$dir/c.json" --out "$dir/r${nl}touch X" --shards 2 --dry-run
refused "--out" "$dir" cluster submit "$dir/c.json" --out "$dir/r\\x" --shards 2 --dry-run
mkdir "$dir/new${nl}line"
refused "the current directory" "$dir/new${nl}line" "${submit[@]}"
refused "--partition" "$dir" cluster submit --resume "$out" --partition "p${nl}touch X" --dry-run
echo "cluster_scripts: hostile values quoted or refused, scripts run whole: ok"
