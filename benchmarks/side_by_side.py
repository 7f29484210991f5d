#!/usr/bin/env python3
"""Old and new ltca-bench binaries run side by side on this machine (issue 9, "no speed regression").

    benchmarks/side_by_side.py OLD_BENCH NEW_BENCH [ROUNDS]

Runs the two harnesses alternately ROUNDS times (default 3: old, new, old, new, ...), each with
its default matrix and 3 repeats, and prints a markdown table of the per-position median time of
every run (the best of the rounds for each binary: the least disturbed), with the ratio new/old.
Rows are matched by case, solver, kinematics, tolerance, preset and geometry mode: like with like.
Not a timed test: the figures go to docs/performance-notes.md by hand, with this command.

    benchmarks/side_by_side.py --rows OLD_BENCH NEW_BENCH [ROUNDS]

Issue 29: its rows of Liu Table 1 (ISSUE29_ROWS), each `ltca-bench --profile ROW` of the two
binaries alternately ROUNDS times (default 3), the fastest total time per position of each; JSON
on stdout. `ltca-bench --docs docs --baseline OLD_BENCH` runs this and writes the table.

    benchmarks/side_by_side.py --self BENCH [ROUNDS]

The same rows of one binary alone (JSON rows with `us`): what `ltca-bench --docs` judges issue
29's bars on when it has no baseline.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile


def run(exe, out):
    subprocess.run([exe, "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    with open(os.path.join(out, "bench.csv"), encoding="utf-8") as f:
        return {(r["case"], r["solver"], r["kinematics"], r["torque_tolerance"], r["preset"], r["geometry_mode"]):
                float(r["seconds_per_position_median"]) for r in csv.DictReader(f)}


# Issue 29's rows: the per-position time of each, the stage (mesh states) included.
ISSUE29_ROWS = [
    "liu2021_table1/compatibility linearised tol 1e-10",
    "liu2021_table1/bisection linearised tol 1e-10",
    "liu2021_table1/compatibility exact tol 1e-10",
    "liu2021_table1/bisection exact tol 1e-10",
    "liu2021_table1/energy-qp linearised tol 1e-10",
    "liu2021_table1/energy-qp exact tol 1e-10",
    "liu2021_table1/bisection exact tol 0.01 (liu2021)",
    "liu2021_table1/bisection exact tol 0.01 (liu2021), elements 800x100",
]


def profile(exe, row, loops):
    """The fastest total us/position of `ltca-bench --profile ROW --loops N`."""
    text = subprocess.run([exe, "--profile", row, "--loops", str(loops)], capture_output=True, text=True,
                          check=False).stdout
    total = text.split("total ")[-1]
    return float(total.split("[")[1].split("]")[0])


def loops_of(row):
    return 3 if "elements" in row else (10 if "exact" in row or "energy" in row else 100)


def self_mode(exe, rounds):
    """`--self BENCH [ROUNDS]`: issue 29's rows of one binary, the fastest of ROUNDS runs; JSON."""
    out = []
    for row in ISSUE29_ROWS:
        best = min(profile(exe, row, loops_of(row)) for _ in range(rounds))
        out.append({"row": row, "us": best, "loops": loops_of(row), "rounds": rounds})
    json.dump({"rows": out}, sys.stdout)


def rows_mode(old_exe, new_exe, rounds):
    """`--rows OLD NEW [ROUNDS]`: issue 29's rows, each `ltca-bench --profile` of the old and the new
    binary alternately ROUNDS times, the fastest of each; JSON on stdout."""
    out = []
    for row in ISSUE29_ROWS:
        loops = loops_of(row)
        best = {"old": float("inf"), "new": float("inf")}
        for _ in range(rounds):
            for tag, exe in (("old", old_exe), ("new", new_exe)):
                best[tag] = min(best[tag], profile(exe, row, loops))
        out.append({"row": row, "old_us": best["old"], "new_us": best["new"], "loops": loops, "rounds": rounds})
    json.dump({"rows": out}, sys.stdout)


def main():
    if sys.argv[1] == "--self":
        self_mode(sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 3)
        return
    if sys.argv[1] == "--rows":
        rows_mode(sys.argv[2], sys.argv[3], int(sys.argv[4]) if len(sys.argv) > 4 else 3)
        return
    old_exe, new_exe = sys.argv[1:3]
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    best = {"old": {}, "new": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(rounds):
            for tag, exe in (("old", old_exe), ("new", new_exe)):
                for key, t in run(exe, os.path.join(tmp, f"{tag}{k}")).items():
                    best[tag][key] = min(t, best[tag].get(key, t))
    print("| case | setting | old us/position | new us/position | new / old |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for key in sorted(set(best["old"]) & set(best["new"])):
        o, n = best["old"][key] * 1e6, best["new"][key] * 1e6
        case, solver, kin, tol, preset, mode = key
        setting = " ".join(x for x in (solver, kin, f"tol {tol}", preset, mode if mode != "analytic" else "") if x)
        print(f"| {case} | {setting} | {o:.1f} | {n:.1f} | {n / o:.3f} |")
        worst = max(worst, n / o)
    print(f"\nworst ratio new/old: {worst:.3f} over {len(set(best['old']) & set(best['new']))} runs, best of {rounds} rounds each")


if __name__ == "__main__":
    main()
