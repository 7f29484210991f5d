#!/usr/bin/env python3
"""`ltca --version` and a compatibility solve map none of the heavy libraries; the runs that need
them load them (docs/architecture.md, "Modules").

    check_start_up_libraries.py LTCA CASES_DIR

The dynamic loader's own record (LD_DEBUG=files, glibc's ld.so(8)) names every shared object the
process maps, at start-up and by dlopen until it exits. Checked:
- the executable names none of them (ldd);
- `ltca --version` and `ltca solve liu2021_table1.toml --solver compatibility --json -` (its 91
  positions; the JSON on stdout parses) map none of OpenMPI, PLplot, Ipopt, MUMPS or CHOLMOD;
- the loader's record does show them when a run needs them, so that the check can fail: energy-qp
  loads ltca_ipopt.so and Ipopt, the pin-bending deck (coupled pins) loads CHOLMOD, --svg loads
  ltca_plots.so and PLplot.
"""
import json
import os
import re
import subprocess
import sys

ltca, cases = sys.argv[1:3]
HEAVY = {"OpenMPI": r"libmpi\.|libopen-pal|libopen-rte", "PLplot": r"libplplot", "Ipopt": r"libipopt|ltca_ipopt\.so",
         "MUMPS": r"libdmumps|libmumps", "CHOLMOD": r"libcholmod"}
problems = []


def mapped(argv):
    """The shared objects the loader maps in the run of argv (LD_DEBUG=files), and the run."""
    env = dict(os.environ, LD_DEBUG="files")
    r = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=300)
    files = set(re.findall(r"file=(\S+)", r.stderr))
    if not files:
        problems.append(f"{' '.join(argv[1:])}: no LD_DEBUG=files record (glibc's loader): the check cannot see")
    return files, r


def heavy(files):
    return sorted(name for name, pattern in HEAVY.items() if any(re.search(pattern, f) for f in files))


ldd = subprocess.run(["ldd", ltca], capture_output=True, text=True).stdout
named = heavy(ldd.split())
if named:
    problems.append(f"the executable itself needs {named} (ldd)")

deck = os.path.join(cases, "liu2021_table1.toml")
for argv in ([ltca, "--version"], [ltca, "solve", deck, "--solver", "compatibility", "--json", "-"]):
    files, r = mapped(argv)
    if r.returncode != 0:
        problems.append(f"{' '.join(argv[1:])}: exit {r.returncode}")
    if "--json" in argv:
        try:
            positions = len(json.loads(r.stdout)["positions"])
        except (ValueError, KeyError, IndexError) as e:
            positions = f"no JSON ({e})"
        if positions != 91:
            problems.append(f"the compatibility sweep has {positions} positions, expected 91")
    if heavy(files):
        problems.append(f"{' '.join(argv[1:])} maps {heavy(files)}: " + ", ".join(sorted(files)))

# The controls: a run that needs a library loads it, and the record shows it.
controls = [
    ([ltca, "solve", deck, "--solver", "energy-qp", "--set", "sweep.positions=2"], {"Ipopt", "MUMPS"}),
    ([ltca, "solve", os.path.join(cases, "pin_bending.toml"), "--set", "sweep.positions=2"], {"CHOLMOD"}),
    ([ltca, "solve", deck, "--set", "sweep.positions=2", "--svg", os.devnull], {"PLplot"}),
]
for argv, expected in controls:
    files, r = mapped(argv)
    if r.returncode != 0:
        problems.append(f"{' '.join(argv[1:])}: exit {r.returncode}: {r.stderr[-500:]}")
    missing = expected - set(heavy(files))
    if missing:
        problems.append(f"{' '.join(argv[1:])} did not load {sorted(missing)} (the loader's record: {sorted(files)})")
if problems:
    sys.exit("\n".join(problems))
print("start-up maps none of", ", ".join(HEAVY), "; the runs that need them load them")
