#!/usr/bin/env python3
"""The front-ends before and after the redesign to one result per analysis, side by side.

    redesign_timing.py OLD_LTCA OLD_PYDIR NEW_LTCA NEW_PYDIR [ROUNDS]

OLD_* and NEW_* are two builds' `ltca` and the folders holding their Python module (`ltca*.so`).
Two jobs, each run ROUNDS times (default 3) alternately old, new, and the fastest of each kept:

- `ltca report` of cases/rv_two_discs.toml with friction, operation and tolerances added (the
  [operation] and [friction] of cases/jiang2022_table2_efficiency.toml, the [tolerances] of
  cases/liu2021_tolerances.toml with its samples cut to --samples 200), every section of the page;
- the Python 100-deck sweep, benchmarks/python_sweep.py (its `python_seconds`: 100 decks built
  and solved in the module).

Prints one JSON object with both times of both jobs and a Markdown table (docs/performance.md).
Not a timed test: a measurement on this machine, quoted with the machine.
"""
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

root = pathlib.Path(__file__).resolve().parents[1]


def section(path, name):
    """The text of [name] in the deck at path, up to the next section."""
    text = (root / path).read_text()
    m = re.search(r"^\[" + re.escape(name) + r"\]\n(.*?)(?=^\[|\Z)", text, re.S | re.M)
    if not m:
        sys.exit(f"redesign_timing: no [{name}] in {path}")
    return f"[{name}]\n{m.group(1)}"


def report_seconds(ltca, deck, out):
    start = time.perf_counter()
    run = subprocess.run([ltca, "report", str(deck), "-o", str(out), "--samples", "200"], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if run.returncode != 0:
        sys.exit(f"redesign_timing: {ltca} report exited {run.returncode}: {run.stderr[-2000:]}")
    return seconds


def python_seconds(ltca, pydir):
    env = dict(os.environ, PYTHONPATH=str(pydir))
    run = subprocess.run([sys.executable, str(root / "benchmarks/python_sweep.py"), ltca], capture_output=True, text=True, env=env)
    if run.returncode != 0:
        sys.exit(f"redesign_timing: python_sweep.py with {pydir} exited {run.returncode}: {run.stderr[-2000:]}")
    return json.loads(run.stdout)["python_seconds"]


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    old_ltca, old_py, new_ltca, new_py = sys.argv[1:5]
    rounds = int(sys.argv[5]) if len(sys.argv) > 5 else 3
    with tempfile.TemporaryDirectory() as tmp:
        deck = pathlib.Path(tmp) / "rv_two_discs_friction_tolerances.toml"
        deck.write_text((root / "cases/rv_two_discs.toml").read_text() + "\n" +
                        section("cases/jiang2022_table2_efficiency.toml", "operation") + "\n" +
                        section("cases/jiang2022_table2_efficiency.toml", "friction") + "\n" +
                        section("cases/liu2021_tolerances.toml", "tolerances"))
        times = {"report": {"old": [], "new": []}, "python": {"old": [], "new": []}}
        for r in range(rounds):
            for which, ltca, pydir in (("old", old_ltca, old_py), ("new", new_ltca, new_py)):
                times["report"][which].append(report_seconds(ltca, deck, pathlib.Path(tmp) / f"report-{which}-{r}"))
                times["python"][which].append(python_seconds(ltca, pydir))
    best = {job: {w: min(v) for w, v in t.items()} for job, t in times.items()}
    print(json.dumps({"rounds": rounds, "times_s": times, "fastest_s": best}))
    print()
    print("| job | before (s) | after (s) | after / before |")
    print("|---|---|---|---|")
    for job, label in (("report", "`ltca report` cases/rv_two_discs.toml + friction + tolerances (200 samples)"),
                       ("python", "Python: 100 decks built and solved (benchmarks/python_sweep.py)")):
        b = best[job]
        print(f"| {label} | {b['old']:.3f} | {b['new']:.3f} | {b['new'] / b['old']:.3f} |")


if __name__ == "__main__":
    main()
