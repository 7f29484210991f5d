#!/usr/bin/env python3
"""Issue 30's benchmark: a sweep of 100 decks built in Python against 100 `ltca solve` processes.

    python_sweep.py LTCA [DECKS [SOLVER]]    (with the module on PYTHONPATH; run by ltca-bench)

The decks: cases/liu2021_optimise.toml (Liu Table 1 pair, one mesh period at 19 positions) with the offset modification dR_p stepped over DECKS values
from -30 to -8 um (dR_rp = -4 um). The module's loop builds each deck (Deck.update) and solves it;
the processes' loop runs `ltca solve cases/liu2021_optimise.toml --set ... --json -` and reads its
JSON, as a script that shells out does. Both use the same solver (SOLVER, default the
deck's: bisection) and give the same pp TE for every deck (checked). Prints one JSON object: decks,
solver, python_seconds, processes_seconds, ratio (processes / python).
"""
import json
import pathlib
import subprocess
import sys
import time

import ltca

ltca_exe = sys.argv[1]
count = int(sys.argv[2]) if len(sys.argv) > 2 else 100
solver = sys.argv[3] if len(sys.argv) > 3 else None
root = pathlib.Path(__file__).resolve().parents[1]
deck_path = str(root / "cases/liu2021_optimise.toml")
offsets = [(-30.0 + 22.0 * i / (count - 1)) / 1000.0 for i in range(count)]
sets = lambda dp: {"modification.pin_radius_mm": -0.004, "modification.pin_circle_radius_mm": dp}

start = time.perf_counter()
base = ltca.Deck.load(deck_path)
python_pp = []
for dp in offsets:
    python_pp.append(ltca.solve(base.update(sets(dp)), solver=solver).summary["pp_te_arcsec"])
python_seconds = time.perf_counter() - start

start = time.perf_counter()
process_pp = []
for dp in offsets:
    args = [ltca_exe, "solve", deck_path, "--json", "-"] + (["--solver", solver] if solver else [])
    for k, v in sets(dp).items():
        args += ["--set", f"{k}={v!r}"]
    run = subprocess.run(args, capture_output=True, text=True)
    process_pp.append(json.loads(run.stdout)["summary"]["pp_te_arcsec"])
processes_seconds = time.perf_counter() - start

if python_pp != process_pp:
    sys.exit("python_sweep: the module and the processes disagree")
print(json.dumps({"decks": count, "solver": solver or "the deck's", "python_seconds": python_seconds, "processes_seconds": processes_seconds,
                  "ratio": processes_seconds / python_seconds}))
