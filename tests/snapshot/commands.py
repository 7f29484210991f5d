#!/usr/bin/env python3
"""Snapshot of every ltca command on every deck before the issue-24 refactoring, and its check.

    commands.py make  LTCA CASES OUT.jsonl          # record (then: xz -9 OUT.jsonl)
    commands.py check LTCA CASES SNAPSHOT.jsonl.xz DECK [--all]

`make` runs, for every deck in CASES (ltca's working directory is CASES and the deck is given
relative to it, so `case.deck` and messages read the same wherever the tree is):

    geometry; mesh --crank-deg 0; backlash --kinematics K; solve --solver S --kinematics K;
    compare --solvers (all four) --kinematics K; stiffness --crank-deg 0;
    efficiency (a deck with [friction] and [operation]);
    tolerance --samples 20 --threads 1 (a deck with [tolerances]; the worst case is kept);
    report -o DIR (with --set tolerances.samples=20 on a deck with [tolerances]), reading back
    the JSON documents it leaves in DIR;

for S in bisection, energy-qp, energy-groups, compatibility and K in linearised, exact. Every
command but report writes `--json -`. One JSON line per run: deck, command, args (after the
deck), exit code, the seconds it took (`generated_wall_seconds`, never compared), and `json`:
the document with every field of TIMING dropped (at any depth), or for report {file: document}.
A run that fails (exit 2: the command does not apply, e.g. a deck without [material]; or no
JSON at all) keeps the last line of its standard error as `message` (report keeps the documents
it wrote before failing too). Python writes a float as the shortest text
that reads back to the same double.

Sampling: a run that took more than SAMPLE_SECONDS is kept whole in the file (`checked` false)
and recorded again at its sweep's first and middle crank angles, each run alone with
`--set sweep.crank_start_deg=C --set sweep.positions=1` (`checked` true, `sampled_from` naming
the whole run's args). The crank angles are the deck's sweep as its linearised backlash gives it
back. `check` runs only the checked records (`--all`: every record, the whole slow runs too).

`check` re-runs one deck's records and compares: exit codes, strings, booleans, nulls, integers,
object keys and array lengths exactly; every float to RELATIVE (1e-12) relative, or, near zero,
to an absolute floor by the field's unit: ABSOLUTE_BY_SUFFIX (1e-9 in arcsec, arcmin, um, mm,
deg, MPa), 1e-12 otherwise (N, N*m, J, W, efficiencies, residuals). An array element takes the
floor of the field that holds the array. Prints the mismatches; exit 1 on any.

It is a regression anchor, not a validation: it records what the code computed at the commit
named in tests/snapshot/README.md, so that a refactoring can show it changed no number.
"""
import json
import lzma
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

SOLVERS = ["bisection", "energy-qp", "energy-groups", "compatibility"]
KINEMATICS = ["linearised", "exact"]
TOLERANCE_SAMPLES = "20"
SAMPLE_SECONDS = 1.0
RELATIVE = 1e-12
ABSOLUTE_DEFAULT = 1e-12
ABSOLUTE_BY_SUFFIX = {"_arcsec": 1e-9, "_arcmin": 1e-9, "_um": 1e-9, "_mm": 1e-9, "_deg": 1e-9,
                      "_mpa": 1e-9}
# Fields that measure time or the machine, dropped at any depth (found by reading every command's
# output): wall_seconds (summaries, compare's solvers, tolerance's worst_case),
# loaded_solve_seconds (efficiency), samples_per_second (tolerance), threads and mpi_ranks
# (tolerance: its samples do not depend on them).
TIMING = {"wall_seconds", "loaded_solve_seconds", "samples_per_second", "threads", "mpi_ranks"}


def deck_sections(path):
    with open(path, encoding="utf-8") as f:
        return {line.strip().split("]")[0] + "]" for line in f if line.lstrip().startswith("[")}


def runs_of(cases, deck):
    """The (command, args) of one deck, args after the deck."""
    sections = deck_sections(os.path.join(cases, deck))
    runs = [("geometry", []), ("mesh", ["--crank-deg", "0"])]
    runs += [("backlash", ["--kinematics", k]) for k in KINEMATICS]
    runs += [("solve", ["--solver", s, "--kinematics", k]) for s in SOLVERS for k in KINEMATICS]
    runs += [("compare", ["--solvers", ",".join(SOLVERS), "--kinematics", k]) for k in KINEMATICS]
    runs.append(("stiffness", ["--crank-deg", "0"]))
    if "[friction]" in sections and "[operation]" in sections:
        runs.append(("efficiency", []))
    if "[tolerances]" in sections:
        runs.append(("tolerance", ["--samples", TOLERANCE_SAMPLES, "--threads", "1"]))
        runs.append(("report", ["--set", f"tolerances.samples={TOLERANCE_SAMPLES}"]))
    else:
        runs.append(("report", []))
    return runs


def strip(doc):
    if isinstance(doc, dict):
        return {k: strip(v) for k, v in doc.items() if k not in TIMING}
    if isinstance(doc, list):
        return [strip(v) for v in doc]
    return doc


def run(exe, cases, deck, command, args):
    """Runs one command; returns (exit code, stripped JSON or None, message or None, seconds)."""
    with tempfile.TemporaryDirectory() as tmp:
        argv = [exe, command, deck, *args]
        argv += ["-o", tmp] if command == "report" else ["--json", "-"]
        start = time.monotonic()
        proc = subprocess.run(argv, cwd=cases, capture_output=True, text=True, check=False)
        wall = time.monotonic() - start
        doc = None
        if command == "report":
            files = sorted(f for f in os.listdir(tmp) if f.endswith(".json"))
            if files:
                doc = {}
                for name in files:
                    with open(os.path.join(tmp, name), encoding="utf-8") as f:
                        doc[name] = strip(json.load(f))
        elif proc.stdout.strip():
            doc = strip(json.loads(proc.stdout))
        message = None
        if doc is None or proc.returncode >= 2:
            lines = [line for line in proc.stderr.splitlines() if line.strip()]
            message = lines[-1] if lines else ""
        return proc.returncode, doc, message, wall


def record(exe, cases, deck, command, args, checked=True, sampled_from=None):
    code, doc, message, wall = run(exe, cases, deck, command, args)
    r = {"deck": deck, "command": command, "args": args, "exit": code, "checked": checked,
         "generated_wall_seconds": round(wall, 2)}
    if sampled_from is not None:
        r["sampled_from"] = sampled_from
    if doc is not None:
        r["json"] = doc
    if message is not None:
        r["message"] = message
    return r


def sweep_cranks(records, deck):
    """The deck's crank angles, as its linearised backlash gives them back (None: no positions)."""
    for r in records:
        if r["deck"] == deck and r["command"] == "backlash" and r["args"][-1] == "linearised":
            positions = (r.get("json") or {}).get("positions") or []
            return [p["crank_deg"] for p in positions] or None
    return None


def make(exe, cases, out):
    exe = os.path.abspath(exe)
    start = time.monotonic()
    decks = sorted(os.path.relpath(os.path.join(d, f), cases)
                   for d, _, files in os.walk(cases) for f in files if f.endswith(".toml"))
    jobs = [(d, c, a) for d in decks for c, a in runs_of(cases, d)]
    with ThreadPoolExecutor(max_workers=2) as pool:
        records = list(pool.map(lambda j: record(exe, cases, *j), jobs))
    # The slow ones: keep them whole, unchecked, and record their first and middle positions alone.
    samples = []
    for r in records:
        if r["generated_wall_seconds"] <= SAMPLE_SECONDS or r["command"] in ("geometry", "mesh"):
            continue
        cranks = sweep_cranks(records, r["deck"])
        if cranks is None:
            continue
        r["checked"] = False
        for c in sorted({cranks[0], cranks[len(cranks) // 2]}):
            args = [*r["args"], "--set", f"sweep.crank_start_deg={c!r}", "--set", "sweep.positions=1"]
            samples.append((r["deck"], r["command"], args, True, r["args"]))
    with ThreadPoolExecutor(max_workers=2) as pool:
        records += list(pool.map(lambda j: record(exe, cases, *j), samples))
    records.sort(key=lambda r: r["deck"])
    with open(out, "w", encoding="utf-8") as f:
        for r in records:
            f.write(json.dumps(r, sort_keys=True, separators=(",", ":")) + "\n")
    slow = [r for r in records if r["checked"] and r["generated_wall_seconds"] > SAMPLE_SECONDS]
    print(f"{len(decks)} decks, {len(records)} runs ({len(samples)} of them one position of a "
          f"slow run) -> {out}")
    print(f"checked runs took {sum(r['generated_wall_seconds'] for r in records if r['checked']):.1f} s "
          f"({len(slow)} still over {SAMPLE_SECONDS} s)")
    print(f"recording took {time.monotonic() - start:.1f} s")


def floor_of(key):
    for suffix, value in ABSOLUTE_BY_SUFFIX.items():
        if key.endswith(suffix):
            return value
    return ABSOLUTE_DEFAULT


def compare(problems, where, key, got, want):
    """Appends to problems every difference between got and want (key: the field's name)."""
    if isinstance(want, dict):
        if not isinstance(got, dict):
            problems.append(f"{where}: {type(got).__name__} != object")
            return
        for k in sorted(set(got) | set(want)):
            if k not in want or k not in got:
                problems.append(f"{where}.{k}: {'extra' if k not in want else 'missing'}")
            else:
                compare(problems, f"{where}.{k}", k, got[k], want[k])
        return
    if isinstance(want, list):
        if not isinstance(got, list) or len(got) != len(want):
            problems.append(f"{where}: length {len(got) if isinstance(got, list) else got!r} != {len(want)}")
            return
        for i, (g, w) in enumerate(zip(got, want)):
            compare(problems, f"{where}[{i}]", key, g, w)
        return
    number = (int, float)
    if (isinstance(want, float) and isinstance(got, number) and not isinstance(got, bool)) or \
       (isinstance(got, float) and isinstance(want, number) and not isinstance(want, bool)):
        if abs(got - want) > max(RELATIVE * abs(want), floor_of(key)):
            problems.append(f"{where}: {got!r} != {want!r} (diff {abs(got - want):.3g})")
        return
    if type(got) is not type(want) or got != want:
        problems.append(f"{where}: {got!r} != {want!r}")


def check_run(exe, cases, want):
    name = f"{want['command']} {want['deck']} {' '.join(want['args'])}"
    code, doc, message, _ = run(exe, cases, want["deck"], want["command"], want["args"])
    problems = []
    compare(problems, f"{name}: exit", "exit", code, want["exit"])
    compare(problems, f"{name}: json", "json", doc, want.get("json"))
    compare(problems, f"{name}: message", "message", message, want.get("message"))
    return problems


def check(exe, cases, snapshot, deck, every=False):
    exe = os.path.abspath(exe)
    with lzma.open(snapshot, "rt", encoding="utf-8") as f:
        wanted = [r for r in map(json.loads, f) if r["deck"] == deck and (every or r["checked"])]
    if not wanted:
        print(f"no run of {deck} in {snapshot}")
        return 1
    start = time.monotonic()
    problems = [line for w in wanted for line in check_run(exe, cases, w)]
    for line in problems[:40]:
        print(line)
    if len(problems) > 40:
        print(f"... and {len(problems) - 40} more")
    print(f"{deck}: {len(wanted)} runs in {time.monotonic() - start:.1f} s, {len(problems)} mismatches")
    return 1 if problems else 0


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "make":
        make(*sys.argv[2:5])
        return 0
    if len(sys.argv) in (6, 7) and sys.argv[1] == "check" and sys.argv[6:] in ([], ["--all"]):
        return check(*sys.argv[2:6], every=len(sys.argv) == 7)
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main())
