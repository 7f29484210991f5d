#!/usr/bin/env python3
"""The stage's elastic disc body's FE set-up, an old build beside a new one (issue 48's 10 s budget).

    stage_body_timing.py OLD_LTCA NEW_LTCA [ROUNDS]

Each round runs, for each build in turn (the order alternating from round to round, so that the
machine's load falls on both alike), one position of

- cases/stage/cycloidal_drive.toml (8 output-pin holes in the body, a 28 mm bore clamped), and
- cases/stage/rv_two_discs_cranks.toml (two discs, three crank holes each, an 8 mm bore),

each with `--set disc.body=elastic` and rigid. CPU time is `perf stat -e task-clock` of the whole
process; the body's set-up is elastic less rigid (for the RV, two discs of two designs: per disc
design, half of it). The median and the range of ROUNDS rounds (default 5) are printed with the
machine's load average before and after, and the largest differences between the two builds'
elastic outputs (rotation, every pin, output-pin, bearing and roller force; relative to the largest
of its kind). Not a timed test: a measurement on this machine, quoted with the machine.
"""
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

root = pathlib.Path(__file__).resolve().parents[1]
DECKS = {
    "cycloidal drive": ("cases/stage/cycloidal_drive.toml", ["--set", "disc.bore_radius_mm=28"]),
    "RV (two discs)": ("cases/stage/rv_two_discs_cranks.toml", ["--set", "disc.bore_radius_mm=8"]),
}
ELASTIC = ["--set", 'disc.body="elastic"']


def task_clock(args):
    """CPU seconds of the command by perf stat's task-clock."""
    with tempfile.NamedTemporaryFile("r", suffix=".perf") as out:
        run = subprocess.run(["perf", "stat", "-x", ",", "-e", "task-clock", "-o", out.name, *args],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if run.returncode != 0:
            sys.exit(f"stage_body_timing: {' '.join(args)} exited {run.returncode}: {run.stderr[-2000:]}")
        for line in out.read().splitlines():
            fields = line.split(",")
            if len(fields) > 2 and fields[2].startswith("task-clock"):
                return float(fields[0]) / 1000.0
    sys.exit("stage_body_timing: no task-clock in perf stat's output")


def command(ltca, deck, elastic, json_path):
    path, extra = DECKS[deck]
    return [ltca, "solve", str(root / path), "--set", "sweep.positions=1", *(ELASTIC + extra if elastic else []),
            "--json", json_path]


def forces(doc):
    """The position's figures by kind: rotation, and the forces of each kind."""
    p = doc["positions"][0]
    kinds = {"TE (rotation)": [p["te_arcsec"]], "pin forces": p["pin_force_n"]}
    stage = p.get("stage", {})
    for disc in stage.get("discs", []):
        kinds.setdefault("disc rotations", []).append(disc["rotation_arcsec"])
        for key in ("bearing_load_n", "output_pin_force_n", "roller_load_n"):
            if key in disc:
                value = disc[key]
                flat = [x for row in value for x in (row if isinstance(row, list) else [row])] \
                    if isinstance(value, list) else [value]
                kinds.setdefault(key, []).extend(flat)
    return kinds


def difference(a, b):
    out = {}
    fa, fb = forces(a), forces(b)
    for kind in fa:
        x, y = fa[kind], fb[kind]
        scale = max(abs(v) for v in x) or 1.0
        out[kind] = max(abs(u - v) for u, v in zip(x, y)) / scale if len(x) == len(y) else float("inf")
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    builds = {"old": sys.argv[1], "new": sys.argv[2]}
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    load_before = os.getloadavg()
    times = {(b, d, e): [] for b in builds for d in DECKS for e in (False, True)}
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="stage_body_timing."))
    for r in range(rounds):
        order = list(builds) if r % 2 == 0 else list(reversed(builds))
        for b in order:
            for d in DECKS:
                for e in (True, False):
                    out = tmp / f"{b}-{'elastic' if e else 'rigid'}-{d.split()[0]}.json"
                    times[(b, d, e)].append(task_clock(command(builds[b], d, e, str(out))))
    load_after = os.getloadavg()
    print(f"{rounds} rounds, old and new alternating; load average {load_before[0]:.1f} before, "
          f"{load_after[0]:.1f} after (1 min)")
    print()
    print("| deck, one position, CPU by perf stat task-clock (median, range) | old | new |")
    print("|---|---|---|")

    def cell(values):
        return f"{statistics.median(values):.3f} s ({min(values):.3f}-{max(values):.3f})"

    for d in DECKS:
        for e in (False, True):
            label = f"{d}, {'elastic' if e else 'rigid'} body, whole process"
            print(f"| {label} | {cell(times[('old', d, e)])} | {cell(times[('new', d, e)])} |")
        designs = 2 if d.startswith("RV") else 1
        setup = {b: [(x - y) / designs for x, y in zip(times[(b, d, True)], times[(b, d, False)])] for b in builds}
        label = f"{d}: the body's set-up (elastic less rigid{', per disc design' if designs > 1 else ''})"
        print(f"| {label} | {cell(setup['old'])} | {cell(setup['new'])} |")
    print()
    for d in DECKS:
        key = d.split()[0]
        a = json.loads((tmp / f"old-elastic-{key}.json").read_text())
        b = json.loads((tmp / f"new-elastic-{key}.json").read_text())
        diff = difference(a, b)
        print(f"{d}, elastic, new against old (largest difference relative to the largest of its kind): " +
              ", ".join(f"{k} {v:.1e}" for k, v in diff.items()))


if __name__ == "__main__":
    main()
