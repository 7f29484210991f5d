#!/usr/bin/env python3
"""The Ipopt module (ltca_ipopt.so) refused when it is missing or was built from another ltca.

    check_ipopt_module.py LTCA STALE_DIR DECK

STALE_DIR holds tests/solvers/stale_ipopt_module.cpp built as ltca_ipopt.so, whose ABI text is
another version's (ltca 0.0.1, Ipopt bridge 0); LTCA_MODULE_DIR makes a folder the only one ltca
looks for modules in (ltca/solvers/modules.hpp). With the stale module and with an empty folder,
`ltca solve --solver energy-qp` must exit 1 (not crash: the stale module's other entry points
abort), say `ltca: error:`, name ltca_ipopt.so and why (both ABI texts; "not found" and the folder
searched), and write no JSON (outputs are all or nothing). The registry still lists energy-qp
(an unknown solver's message names every registered one: no module is needed for that), and a
compatibility solve succeeds (it never loads the module).
"""
import os
import subprocess
import sys
import tempfile

ltca, stale, deck = sys.argv[1:4]
problems = []
with tempfile.TemporaryDirectory() as empty, tempfile.TemporaryDirectory() as out:
    cases = {
        stale: ("ltca_ipopt.so", "built from another version of ltca", "ltca 0.0.1, Ipopt bridge 0", "Ipopt bridge 1"),
        empty: ("ltca_ipopt.so", "cannot be loaded: not found", f"looked in {empty}", "energy-qp"),
    }
    for folder, says in cases.items():
        env = dict(os.environ, LTCA_MODULE_DIR=folder)
        js = os.path.join(out, "qp.json")
        r = subprocess.run([ltca, "solve", deck, "--solver", "energy-qp", "--set", "sweep.positions=2", "--json", js],
                           capture_output=True, text=True, env=env, timeout=120)
        where = "stale module" if folder == stale else "no module"
        if r.returncode != 1:
            problems.append(f"{where}: exit {r.returncode}, expected 1: {r.stderr.strip()}")
        for said in ("ltca: error:",) + says:
            if said not in r.stderr:
                problems.append(f"{where}: the message does not say '{said}': {r.stderr.strip()}")
        if os.path.exists(js):
            problems.append(f"{where}: the JSON was written")
        listed = subprocess.run([ltca, "solve", deck, "--solver", "no-such-solver"], capture_output=True, text=True,
                                env=env, timeout=60)
        if listed.returncode != 2 or "energy-qp" not in listed.stderr:
            problems.append(f"{where}: the registry's list: exit {listed.returncode}: {listed.stderr.strip()}")
        plain = subprocess.run([ltca, "solve", deck, "--solver", "compatibility", "--set", "sweep.positions=2"],
                               capture_output=True, text=True, env=env, timeout=60)
        if plain.returncode != 0:
            problems.append(f"{where}: the compatibility solve: exit {plain.returncode}: {plain.stderr.strip()}")
    print("refused:", r.stderr.strip())
if problems:
    sys.exit("\n".join(problems))
