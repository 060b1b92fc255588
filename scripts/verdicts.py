"""The verdict categories of fits.json (harness/fit.hpp) and their tallies, in one place for
report.py and findings.py. Claims whose subject is pcrt's own scaffolding ("about": "pcrt": the
brute-force oracle's build, the calibration workloads, pcrt's own observations) are checks of
pcrt, and claims of the papers after the thesis ("about": "later": 3DGRT's) are those papers';
both are tallied apart from the thesis's claims."""
GROWTH = ["holds", "exceeds", "inconclusive"]
THRESHOLD = ["meets", "misses"]
LOOP = ["loop_check"]
NOT_JUDGED = ["drifted", "not_judged", "error"]
ORDER = GROWTH + THRESHOLD + LOOP + NOT_JUDGED


def about_pcrt(f):
    return f.get("about") == "pcrt"


def about_later(f):
    return f.get("about") == "later"


def is_growth_claim(f):
    """A fit of a growth claim (judged or not), as opposed to a threshold."""
    return "threshold" not in f and f.get("variable")


def tally(fits):
    counts = {v: 0 for v in ORDER}
    for f in fits:
        counts[f["verdict"]] = counts.get(f["verdict"], 0) + 1
    return counts


def tally_text(fits):
    thesis = [f for f in fits if not about_pcrt(f) and not about_later(f)]
    pcrt = [f for f in fits if about_pcrt(f)]
    later = tally([f for f in fits if about_later(f)])
    c = tally(thesis)
    part = lambda names: ", ".join(f"{c[v]} {v}" for v in names)
    growth = [f for f in thesis if is_growth_claim(f)]
    unjudged = [f for f in growth if f["verdict"] in NOT_JUDGED]
    p = tally(pcrt)
    checks = ", ".join(f"{p[v]} {v}" for v in ORDER if p[v])
    share = 100 * len(unjudged) / len(growth) if growth else 0
    return (f"Thesis growth claims ({sum(c[v] for v in GROWTH)} judged): {part(GROWTH)}. Threshold "
            f"claims: {part(THRESHOLD)}. Loop checks (not confirmations): {c['loop_check']}. Not judged: "
            f"{part(NOT_JUDGED)} ({len(unjudged)} of {len(growth)} growth fits, {share:.0f}%). Checks of "
            f"pcrt, tallied apart ({len(pcrt)}): {checks or 'none'}."
            + (f" Claims of later papers, tallied apart ({sum(later.values())}): "
               + ", ".join(f"{later[v]} {v}" for v in ORDER if later[v]) + "."
               if sum(later.values()) else ""))


def run_main(main, usage, nargs):
    """Runs a results script's main() as a pcrt command runs: fewer than `nargs` arguments print
    the usage; a missing, unreadable or malformed input (a cut fits.json, a runs.csv without a
    column, a value of the wrong type) ends it with one line naming the inputs and status 1,
    never a traceback."""
    import csv
    import sys
    prog = sys.argv[0].rsplit("/", 1)[-1]
    if len(sys.argv) < 1 + nargs:
        print(f"{prog}: usage: {usage}", file=sys.stderr)
        return 1
    try:
        return main()
    except (OSError, ValueError, KeyError, TypeError, IndexError, AttributeError, csv.Error) as e:
        what = f"{type(e).__name__}: {e}".replace("\n", " ")
        print(f"{prog}: {' '.join(sys.argv[1:])}: missing or malformed results ({what})", file=sys.stderr)
        return 1
