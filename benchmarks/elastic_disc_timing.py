#!/usr/bin/env python3
"""The elastic disc's cost beside the rigid disc's (issue 48's speed budget), in one run.

    elastic_disc_timing.py LTCA [ROUNDS] [SAMPLES]

LTCA is a build's `ltca`. Each job runs ROUNDS times (default 3), alternately rigid and elastic,
and the fastest of each is kept:

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
import pathlib
import subprocess
import sys
import time

root = pathlib.Path(__file__).resolve().parents[1]
ELASTIC = ["--set", 'disc.body="elastic"', "--set", "disc.bore_radius_mm=22"]
SIGNED = ["--set", 'contact.rho_convention="signed"']


def seconds(args):
    start = time.perf_counter()
    run = subprocess.run(args, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if run.returncode != 0:
        sys.exit(f"elastic_disc_timing: {' '.join(args)} exited {run.returncode}: {run.stderr[-2000:]}")
    return elapsed


def solve(ltca, positions, extra):
    return seconds([ltca, "solve", str(root / "cases/liu2021_sec52_base.toml"), *SIGNED, "--set",
                    f"sweep.positions={positions}", "--json", "/dev/null", *extra])


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    ltca = sys.argv[1]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    samples = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
    best = {}

    def keep(name, value):
        best[name] = min(best.get(name, float("inf")), value)

    for _ in range(rounds):
        for body, extra in (("rigid", []), ("elastic", ELASTIC)):
            keep(f"one_{body}", solve(ltca, 1, extra))
            for solver in ("bisection", "compatibility", "energy-qp", "energy-groups"):
                for kinematics in ("linearised", "exact"):
                    more = extra + ["--set", f'solver.name="{solver}"', "--set", f'solver.kinematics="{kinematics}"']
                    keep(f"sweep_{body}_{solver}_{kinematics}", solve(ltca, 3001, more))
                    keep(f"one_{body}_{solver}_{kinematics}", solve(ltca, 1, more))
            keep(f"tolerance_{body}", seconds([ltca, "tolerance", str(root / "cases/liu2021_tolerances.toml"), *SIGNED,
                                               "--set", f"tolerances.samples={samples}", "--json", "/dev/null", *extra]))
    setup = best["one_elastic"] - best["one_rigid"]
    rows = []
    for solver in ("bisection", "compatibility", "energy-qp", "energy-groups"):
        for kinematics in ("linearised", "exact"):
            per = {b: (best[f"sweep_{b}_{solver}_{kinematics}"] - best[f"one_{b}_{solver}_{kinematics}"]) / 3000.0
                   for b in ("rigid", "elastic")}
            rows.append((solver, kinematics, per["rigid"], per["elastic"]))
    print(json.dumps({"rounds": rounds, "samples": samples, "fastest_s": best, "setup_s": setup}))
    print()
    print(f"set-up of the FE body (one position, elastic less rigid): {setup:.2f} s")
    print()
    print("| solver | kinematics | rigid (us a position) | elastic (us a position) | elastic / rigid |")
    print("|---|---|---|---|---|")
    for solver, kinematics, r, e in rows:
        print(f"| {solver} | {kinematics} | {r * 1e6:.1f} | {e * 1e6:.1f} | {e / r:.2f} |")
    t_r, t_e = best["tolerance_rigid"], best["tolerance_elastic"]
    print()
    print(f"| `ltca tolerance` cases/liu2021_tolerances.toml, {samples} samples | rigid {t_r:.2f} s | elastic {t_e:.2f} s "
          f"| {t_e / t_r:.2f} |")


if __name__ == "__main__":
    main()
