#!/usr/bin/env python3
"""Old and new ltca-bench binaries run side by side on this machine (issue 9, "no speed regression").

    benchmarks/side_by_side.py OLD_BENCH NEW_BENCH [ROUNDS]

Runs the two harnesses alternately ROUNDS times (default 3: old, new, old, new, ...), each with
its default matrix and 3 repeats, and prints a markdown table of the per-position median time of
every run (the best of the rounds for each binary: the least disturbed), with the ratio new/old.
Rows are matched by case, solver, kinematics, tolerance, preset and geometry mode: like with like.
Not a timed test: the figures go to docs/performance-notes.md by hand, with this command.
"""
import csv
import os
import subprocess
import sys
import tempfile


def run(exe, out):
    subprocess.run([exe, "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    with open(os.path.join(out, "bench.csv"), encoding="utf-8") as f:
        return {(r["case"], r["solver"], r["kinematics"], r["torque_tolerance"], r["preset"], r["geometry_mode"]):
                float(r["seconds_per_position_median"]) for r in csv.DictReader(f)}


def main():
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
