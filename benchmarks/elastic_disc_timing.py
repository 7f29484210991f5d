#!/usr/bin/env python3
"""The elastic disc's cost beside the rigid disc's (issue 48's speed budget), in one run.

    elastic_disc_timing.py LTCA[,LTCA2,...] [ROUNDS] [SAMPLES]

LTCA is a build's `ltca`; several, comma-separated (an old build beside a new one), take turns
round by round, so that the machine's load falls on all alike. Each job runs ROUNDS times (default 3),
alternately rigid and elastic, and the fastest of each is kept. Times are CPU seconds of the child
(user + system, os.wait4: the machine's other load does not count, a second thread's work does),
the wall times beside them:

- set-up: `ltca solve` of cases/liu2021_sec52_base.toml (signed rho) at one position, elastic
  ([disc] body = "elastic", bore 22 mm) less rigid: the FE body's mesh, factorisation and
  condensation (once per body design in a process);
- a position: the same deck at 3,001 positions less 1 position, per position, for every solver
  that takes a coupling, linearised and exact kinematics (elastic / rigid: the budget is 3x);
- a tolerance study: `ltca tolerance cases/liu2021_tolerances.toml` (signed rho) at SAMPLES samples
  (default 1000), elastic / rigid, whole process (the budget is 1.5x).

Prints one JSON object and a Markdown table (docs/fe_disc.md). Not a timed test: a measurement on
this machine, quoted with the machine.
"""
import json
import os
import pathlib
import subprocess
import sys
import time

root = pathlib.Path(__file__).resolve().parents[1]
ELASTIC = ["--set", 'disc.body="elastic"', "--set", "disc.bore_radius_mm=22"]
SIGNED = ["--set", 'contact.rho_convention="signed"']


WALL = {}


def seconds(args):
    """CPU seconds (user + system) of the child; its wall seconds go to WALL."""
    start = time.perf_counter()
    child = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(child.pid, 0)
    stderr = child.stderr.read()
    child.stderr.close()
    child.returncode = os.waitstatus_to_exitcode(status)
    WALL[" ".join(args)] = time.perf_counter() - start
    if child.returncode != 0:
        sys.exit(f"elastic_disc_timing: {' '.join(args)} exited {child.returncode}: {stderr[-2000:]}")
    return usage.ru_utime + usage.ru_stime


def solve(ltca, positions, extra):
    return seconds([ltca, "solve", str(root / "cases/liu2021_sec52_base.toml"), *SIGNED, "--set",
                    f"sweep.positions={positions}", "--json", "/dev/null", *extra])


def measure(ltca, rounds, samples, best):
    def keep(name, value):
        best[name] = min(best.get(name, float("inf")), value)

    for body, extra in (("rigid", []), ("elastic", ELASTIC)):
        keep(f"one_{body}", solve(ltca, 1, extra))
        for solver in ("bisection", "compatibility", "energy-qp", "energy-groups"):
            for kinematics in ("linearised", "exact"):
                more = extra + ["--set", f'solver.name="{solver}"', "--set", f'solver.kinematics="{kinematics}"']
                keep(f"sweep_{body}_{solver}_{kinematics}", solve(ltca, 3001, more))
                keep(f"one_{body}_{solver}_{kinematics}", solve(ltca, 1, more))
        if samples > 0:
            keep(f"tolerance_{body}", seconds([ltca, "tolerance", str(root / "cases/liu2021_tolerances.toml"), *SIGNED,
                                               "--set", f"tolerances.samples={samples}", "--json", "/dev/null", *extra]))


def report(ltca, rounds, samples, best):
    setup = best["one_elastic"] - best["one_rigid"]
    rows = []
    for solver in ("bisection", "compatibility", "energy-qp", "energy-groups"):
        for kinematics in ("linearised", "exact"):
            per = {b: (best[f"sweep_{b}_{solver}_{kinematics}"] - best[f"one_{b}_{solver}_{kinematics}"]) / 3000.0
                   for b in ("rigid", "elastic")}
            rows.append((solver, kinematics, per["rigid"], per["elastic"]))
    print(json.dumps({"ltca": ltca, "rounds": rounds, "samples": samples, "fastest_cpu_s": best, "setup_cpu_s": setup}))
    print()
    print(f"{ltca}: set-up of the FE body (one position, elastic less rigid): {setup:.2f} s CPU")
    print()
    print("| solver | kinematics | rigid (us CPU a position) | elastic (us CPU a position) | elastic / rigid |")
    print("|---|---|---|---|---|")
    for solver, kinematics, r, e in rows:
        print(f"| {solver} | {kinematics} | {r * 1e6:.1f} | {e * 1e6:.1f} | {e / r:.2f} |")
    if samples > 0:
        t_r, t_e = best["tolerance_rigid"], best["tolerance_elastic"]
        print()
        print(f"| `ltca tolerance` cases/liu2021_tolerances.toml, {samples} samples | rigid {t_r:.2f} s CPU | elastic "
              f"{t_e:.2f} s CPU | {t_e / t_r:.2f} |")
    print()


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    builds = sys.argv[1].split(",")
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    samples = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
    best = {ltca: {} for ltca in builds}
    for _ in range(rounds):
        for ltca in builds:
            measure(ltca, rounds, samples, best[ltca])
    for ltca in builds:
        report(ltca, rounds, samples, best[ltca])


if __name__ == "__main__":
    main()
