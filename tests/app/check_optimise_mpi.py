#!/usr/bin/env python3
"""Issue 28: `mpirun -np 2 ltca optimise` gives what one process gives, bit for bit.

    check_optimise_mpi.py LTCA MPIRUN DECK OUT_DIR

A robust search (each design's samples split over the ranks), its map (the points split) and its
Pareto front (the steps split) on a small version of DECK (3 positions, 45 robust samples: the
least that bound the p95 at 90 % confidence). Checked: the per-evaluation CSV (history and map) is
byte for byte the same; the JSON's history, map and front are equal; the two-rank run says it ran
on 2 ranks; the runs found feasible designs, map points and front points, so that the comparison
compares numbers and not only failures.
"""
import json
import os
import subprocess
import sys

ltca, mpirun, deck, out = sys.argv[1:5]
os.makedirs(out, exist_ok=True)
args = ["optimise", deck, "--threads", "1", "--evaluations", "12", "--map", "3",
        "--pareto", "pp_te_arcsec", "--pareto-from", "0.8", "--pareto-to", "3", "--pareto-steps", "3",
        "--set", "sweep.positions=3", "--set", "optimise.robust_samples=45",
        "--set", 'optimise.variables={ "modification.pin_radius_mm" = [-0.012, -0.002], '
                 '"modification.pin_circle_radius_mm" = [-0.03, -0.016] }']
runs = {}
for ranks in (1, 2):
    prefix = [] if ranks == 1 else [mpirun, "--oversubscribe", "-np", "2"]
    csv, js = os.path.join(out, f"optimise_{ranks}.csv"), os.path.join(out, f"optimise_{ranks}.json")
    r = subprocess.run(prefix + [ltca] + args + ["--csv", csv, "--json", js], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{ranks} rank(s): exit {r.returncode}\n{r.stderr}")
    runs[ranks] = (open(csv, "rb").read(), json.load(open(js)))

one, two = runs[1], runs[2]
if one[0] != two[0]:
    sys.exit("the CSV of 2 ranks differs from that of 1 process")
for part in ("history", "map", "pareto"):
    if one[1][part] != two[1][part]:
        sys.exit(f"the JSON's {part} of 2 ranks differs from that of 1 process")
if two[1]["settings"]["mpi_ranks"] != 2 or one[1]["settings"]["mpi_ranks"] != 1:
    sys.exit(f"mpi_ranks: {one[1]['settings']['mpi_ranks']} and {two[1]['settings']['mpi_ranks']}, expected 1 and 2")
feasible = sum(e["feasible"] for e in one[1]["history"])
mapped = sum(e["status"] == "success" for e in one[1]["map"])
front = sum(p["design"] is not None for p in one[1]["pareto"])
if feasible == 0 or mapped == 0 or front == 0:
    sys.exit(f"nothing to compare: {feasible} feasible evaluations, {mapped} map points, {front} front points")
print(f"1 and 2 ranks agree: {len(one[1]['history'])} evaluations ({feasible} feasible), "
      f"{len(one[1]['map'])} map points, {front} front points")
