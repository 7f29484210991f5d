#!/usr/bin/env python3
"""A drawing module (ltca_plots.so) built from another ltca is refused, naming both versions.

    check_stale_module.py LTCA STALE_DIR DECK

STALE_DIR holds tests/app/stale_plots_module.cpp built as ltca_plots.so, whose ABI text is another
version's; LTCA_MODULE_DIR=STALE_DIR makes it the only module ltca finds (app/modules.hpp). The
run with --svg must fail as an output that cannot be written (exit 3, before anything is solved), say that ltca_plots.so was built from another version of ltca,
name both ABI texts, and write no file (outputs are all or nothing); without --svg the module is
never loaded and the same solve succeeds.
"""
import os
import subprocess
import sys
import tempfile

ltca, stale, deck = sys.argv[1:4]
env = dict(os.environ, LTCA_MODULE_DIR=stale)
problems = []
with tempfile.TemporaryDirectory() as out:
    svg, js = os.path.join(out, "s.svg"), os.path.join(out, "s.json")
    r = subprocess.run([ltca, "solve", deck, "--set", "sweep.positions=2", "--json", js, "--svg", svg],
                       capture_output=True, text=True, env=env)
    if r.returncode != 3:
        problems.append(f"exit {r.returncode}, expected 3")
    for said in ("ltca_plots.so", "built from another version of ltca", "ltca 0.0.1, plots ABI 0", "plots ABI 1"):
        if said not in r.stderr:
            problems.append(f"the message does not say '{said}': {r.stderr.strip()}")
    for path in (svg, js):
        if os.path.exists(path):
            problems.append(f"{os.path.basename(path)} was written")
    plain = subprocess.run([ltca, "solve", deck, "--set", "sweep.positions=2"], capture_output=True, text=True, env=env)
    if plain.returncode != 0:
        problems.append(f"without --svg: exit {plain.returncode}: {plain.stderr.strip()}")
if problems:
    sys.exit("\n".join(problems))
print("refused:", r.stderr.strip())
