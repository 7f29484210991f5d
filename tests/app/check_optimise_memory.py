#!/usr/bin/env python3
"""Issue 46 item 13: `ltca optimise` holds no history: its peak memory does not grow with the
evaluations.

    check_optimise_memory.py LTCA PEAK_RSS DECK OUT_DIR

The same search (CRS2 alone, whose population NLopt keeps at a fixed size, on 2 positions a
design) for 2,000 and for 40,000 evaluations with --json and --csv, each run's peak resident memory
measured by PEAK_RSS (benchmarks/peak_rss.cpp: the kernel's count for that process alone). When the
search kept its history (about 0.6 KB an evaluation) the long run took about 23 MB more; now the two
must be within 4 MB. The documents must still hold every evaluation: the JSON's history and the
CSV's rows, indices 0, 1, ... in order, as many as the summary counts.
"""
import csv
import json
import os
import subprocess
import sys

ltca, peak_rss, deck, out = sys.argv[1:5]
os.makedirs(out, exist_ok=True)
SHORT, LONG, ALLOWED_MB = 2000, 40000, 4.0


def run(evaluations):
    js, cs = os.path.join(out, f"optimise_{evaluations}.json"), os.path.join(out, f"optimise_{evaluations}.csv")
    args = [peak_rss, ltca, "optimise", deck, "--threads", "1", "--evaluations", str(evaluations),
            "--set", "sweep.positions=2", "--set", 'optimise.global="crs2"', "--set", 'optimise.local="none"',
            "--json", js, "--csv", cs]
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{evaluations} evaluations: exit {r.returncode}\n{r.stderr}")
    mb = int(r.stdout.strip()) / 1024.0
    doc = json.load(open(js))
    n = doc["summary"]["evaluations"]
    history = doc["history"]
    if len(history) != n or [e["index"] for e in history] != list(range(n)):
        sys.exit(f"{evaluations} evaluations: the JSON's history has {len(history)} items, not 0 .. {n - 1} in order")
    with open(cs, newline="") as f:
        rows = list(csv.DictReader(f))
    if [int(r["index"]) for r in rows] != list(range(n)):
        sys.exit(f"{evaluations} evaluations: the CSV has {len(rows)} rows, not 0 .. {n - 1} in order")
    # Half the evaluations asked still tell: a kept history would add 0.6 KB x 18,000 = 11 MB, well
    # beyond the 4 MB allowed. (CRS2 may converge before the count: since issue 52 the preloaded
    # designs of the box evaluate instead of being rejected, and it stops at about 34,000.)
    if n < evaluations * 0.5:
        sys.exit(f"{evaluations} evaluations asked, {n} made: the search stopped early, the comparison is void")
    os.remove(js)
    os.remove(cs)
    return n, mb


short, long_ = run(SHORT), run(LONG)
print(f"peak resident memory: {short[0]} evaluations {short[1]:.1f} MB, {long_[0]} evaluations {long_[1]:.1f} MB")
if long_[1] - short[1] > ALLOWED_MB:
    sys.exit(f"the long run took {long_[1] - short[1]:.1f} MB more than the short one (allowed {ALLOWED_MB} MB): "
             "the memory grows with the evaluations")
