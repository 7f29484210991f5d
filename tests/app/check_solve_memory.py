#!/usr/bin/env python3
"""`ltca solve --svg` of a long sweep: bounded memory and a bounded, decimated figure.

    check_solve_memory.py LTCA PEAK_RSS DECK

Liu's Table 1 pair (DECK) with the compatibility solver, drawn to SVG, each run's peak resident
memory measured by PEAK_RSS (benchmarks/peak_rss.cpp: the kernel's count for that process alone):
- 100,000 positions over 3,600 deg: under 64 MB (it was 190 MB with a 39 MB drawing before the
  figure kept a bounded series), the SVG under 4 MB, the TE panel titled with its decimation and
  the caption saying it, the maps saying each column is the largest of its positions;
- 4,000 and 9,000 positions over 360 deg: under 64 MB (the mesh states a stage keeps are bounded by
  analysis::Stage::kKeptStatesBytes, 32 MB: with 64 MB the 9,000-position sweep peaked at 70 MB).
"""
import os
import subprocess
import sys
import tempfile

ltca, peak_rss, deck = sys.argv[1:4]
LIMIT_MB, SVG_LIMIT_MB = 64.0, 4.0
problems = []
with tempfile.TemporaryDirectory() as out:
    for positions, end in ((100000, 3600), (9000, 360), (4000, 360)):
        svg = os.path.join(out, f"solve_{positions}.svg")
        r = subprocess.run([peak_rss, ltca, "solve", deck, "--solver", "compatibility", "--set", f"sweep.positions={positions}",
                            "--set", f"sweep.crank_end_deg={end}", "--svg", svg], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"{positions} positions: exit {r.returncode}\n{r.stderr}")
        mb = int(r.stdout.strip().splitlines()[-1]) / 1024.0
        size_mb = os.path.getsize(svg) / 2**20
        text = open(svg, encoding="utf-8", errors="replace").read()
        print(f"{positions} positions: peak resident memory {mb:.1f} MB, SVG {size_mb:.2f} MB")
        if mb >= LIMIT_MB:
            problems.append(f"{positions} positions: peak {mb:.1f} MB, not under {LIMIT_MB} MB")
        if size_mb >= SVG_LIMIT_MB:
            problems.append(f"{positions} positions: SVG {size_mb:.2f} MB, not under {SVG_LIMIT_MB} MB")
        stride = -(-positions // 2000)  # the TE's runs (documents::DecimatedSeries, 2,000 buckets)
        for said in (f"loaded TE, least and largest of every {stride} positions",
                     f"TE drawn as the least and largest of every {stride} positions",
                     f"max of every {-(-positions // 120)} positions"):
            if said not in text:
                problems.append(f"{positions} positions: the SVG does not say '{said}'")
if problems:
    sys.exit("\n".join(problems))
