#!/usr/bin/env python3
"""Snapshot of ltca's outputs before the issue-9 refactoring, and the check that reproduces it.

    snapshot.py make  LTCA CASES OUT.jsonl          # record (then: xz -9 OUT.jsonl)
    snapshot.py check LTCA CASES SNAPSHOT.jsonl.xz DECK
    snapshot.py remake LTCA CASES OLD.jsonl.xz OUT.jsonl DECK...   # re-record DECKs only (then: xz -9)

`make` runs `ltca solve DECK --solver S --kinematics K --json FILE` for every deck in CASES,
every solver and both kinematics, and writes one JSON line per run: the deck (relative to
CASES), solver, kinematics, exit code, the wall time it took, the summary (wall time dropped)
and per position the crank, status, TE and the non-zero pin forces ({pin index: N}). Python
writes a float as the shortest text that reads back to the same double.

`check` re-runs the runs of one deck and compares: exit code, statuses and counts exactly;
every figure to 1e-12 relative, or absolutely near zero to 1e-12 N, 1e-9 arcsec, 1e-9 MPa
(issue 9). A run that took more than SAMPLE_SECONDS to record (energy-qp under exact
kinematics, Li's tooth groups on the 80- to 320-pin scaling decks) is checked at its first and
middle positions, each solved alone (`--set sweep.crank_start_deg=... positions=1`): those runs
carry nothing from one position to the next. (The last position was dropped: its crank, given
back in degrees, came out one ulp off the sweep's in one deck and moved a 3.5 N force by 2e-10 N.) Linearised energy-qp warm-starts each position from the
previous one, so its runs are always checked whole.

This is a regression anchor, not a validation: it records what the code computed at the commit
named in tests/snapshot/README.md, so that a refactoring can show it changed no number.
"""
import json
import lzma
import os
import subprocess
import sys

import snapshot_cli  # beside this script
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

SOLVERS = ["bisection", "energy-qp", "energy-groups", "compatibility"]
KINEMATICS = ["linearised", "exact"]
SAMPLE_SECONDS = 4.0
RELATIVE = 1e-12
# "other": a summary figure added after 9dfef0e (a disc's share, a stage's load): 1e-12 absolute.
ABSOLUTE = {"te": 1e-9, "force": 1e-12, "stress": 1e-9, "crank": 1e-12, "other": 1e-12}
# Issue 29: a faster law inversion and the reuse of a solver's last evaluation move the last bits
# of a force, and the solvers' stopping decisions then follow another path inside the band their
# torque tolerance (1e-10 of T) allows: every figure is compared to SOLVE_PATH_RELATIVE, with a
# force floor of SOLVE_PATH_FORCE_N (about 1e-10 of the torque over the pin-circle radius; see
# tests/snapshot/README.md and commands.py for what was measured). Statuses and counts stay exact.
SOLVE_PATH_RELATIVE = 1e-8
SOLVE_PATH_FORCE_N = 1e-6



# Issue 12 gave a |d| >= 2 deck with a load a default tip relief; issue 26 removed it (no relief is
# assumed). The snapshot recorded their sharp tips, which both relief keys set to 0 keep: these
# decks are still checked with the keys given, which is now also what the deck alone runs.
SHARP_TIPS = {"hard/d2_loaded.toml", "hard/d3_loaded.toml"}
SHARP_TIP_SETTINGS = ["--set", "modification.tip_truncation_mm=0", "--set", "modification.tip_rounding_radius_mm=0"]


def solve(exe, deck_path, solver, kinematics, extra=()):
    """Runs ltca solve; returns (exit code, parsed JSON or None, wall seconds)."""
    if any(deck_path.endswith(deck) for deck in SHARP_TIPS):
        extra = [*SHARP_TIP_SETTINGS, *extra]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.json")
        start = time.monotonic()
        proc = subprocess.run([exe, "solve", deck_path, "--solver", solver, "--kinematics", kinematics,
                               "--json", out, *extra],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        wall = time.monotonic() - start
        if proc.returncode not in (0, 1):
            return proc.returncode, None, wall
        with open(out, encoding="utf-8") as f:
            return proc.returncode, json.load(f), wall


# Issue 46: a balance that the arithmetic cannot resolve (hard/tiny_torque.toml under exact
# kinematics) now carries a warning that says so; the recording predates it, so the warned count
# leaves out the positions whose only warnings are of that kind (commands.py does the same).
RESOLUTION_WARNING = "resolution-limited balance"


def condense(doc):
    summary = dict(doc["summary"])
    summary.pop("wall_seconds", None)
    if "warned_positions" in summary:
        summary["warned_positions"] = sum(
            1 for p in doc["positions"] if any(RESOLUTION_WARNING not in w for w in (p.get("warnings") or [])))
    positions = [{
        "crank_deg": p["crank_deg"],
        "status": p["status"],
        "te_arcsec": p["te_arcsec"],
        "pin_force_n": None if p["pin_force_n"] is None else
        {str(i): v for i, v in enumerate(p["pin_force_n"]) if v != 0.0},
    } for p in doc["positions"]]
    return summary, positions


def record(exe, cases, deck, solver, kinematics):
    code, doc, wall = solve(exe, os.path.join(cases, deck), solver, kinematics)
    r = {"deck": deck, "solver": solver, "kinematics": kinematics, "exit": code,
         "generated_wall_seconds": round(wall, 2)}
    if doc is not None:
        r["summary"], r["positions"] = condense(doc)
    return r


def records_of(exe, cases, decks):
    """Every run of `decks`, in deck, solver and kinematics order."""
    jobs = [(d, s, k) for d in decks for s in SOLVERS for k in KINEMATICS]
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        return list(pool.map(lambda j: record(exe, cases, *j), jobs))


def make(exe, cases, out):
    decks = sorted(os.path.relpath(os.path.join(d, f), cases)
                   for d, _, files in os.walk(cases) for f in files if f.endswith(".toml"))
    records = records_of(exe, cases, decks)
    with open(out, "w", encoding="utf-8") as f:
        for r in records:
            f.write(json.dumps(r, sort_keys=True, separators=(",", ":")) + "\n")
    print(f"{len(records)} runs, {sum(len(r.get('positions', [])) for r in records)} positions -> {out}")


class Mismatch:
    def __init__(self):
        self.lines = []

    def close(self, where, kind, got, want, least=0.0):
        if got is None or want is None:
            if got is not want:
                self.lines.append(f"{where}: {got} != {want}")
            return
        if isinstance(want, (int, str, bool)) and not isinstance(want, float):
            if got != want:
                self.lines.append(f"{where}: {got!r} != {want!r}")
            return
        floor = max(ABSOLUTE[kind], SOLVE_PATH_FORCE_N if kind == "force" else 0.0, least)
        if abs(got - want) > max(SOLVE_PATH_RELATIVE * abs(want), floor):
            self.lines.append(f"{where}: {got!r} != {want!r} (diff {abs(got - want):.3g})")


SUMMARY_KIND = {"mean_te_arcsec": "te", "pp_te_arcsec": "te", "max_pin_force_n": "force",
                "max_contact_stress_mpa": "stress"}


def compare_positions(m, where, got, want):
    m.close(f"{where} crank_deg", "crank", got["crank_deg"], want["crank_deg"])
    m.close(f"{where} status", None, got["status"], want["status"])
    m.close(f"{where} te_arcsec", "te", got["te_arcsec"], want["te_arcsec"])
    gf, wf = got["pin_force_n"], want["pin_force_n"]
    if gf is None or wf is None:
        m.close(f"{where} pin_force_n", None, gf, wf)
        return
    for k in sorted(set(gf) | set(wf), key=int):
        m.close(f"{where} pin {int(k) + 1} force", "force", gf.get(k, 0.0), wf.get(k, 0.0))


def check_run(exe, cases, want):
    name = f"{want['deck']} {want['solver']} {want['kinematics']}"
    m = Mismatch()
    path = os.path.join(cases, want["deck"])
    # energy-qp warm-starts a linearised position from the previous one: only its whole sweep
    # reproduces it. Every other run solves each position from scratch.
    carries = want["solver"] == "energy-qp" and want["kinematics"] == "linearised"
    sampled = not carries and want["generated_wall_seconds"] > SAMPLE_SECONDS
    if not sampled:
        code, doc, _ = solve(exe, path, want["solver"], want["kinematics"])
        m.close(f"{name}: exit code", None, code, want["exit"])
        if doc is None or "summary" not in want:
            return m.lines
        summary, positions = condense(doc)
        want_summary = dict(want["summary"])
        if summary.get("closed_period") and want.get("positions"):
            # Issue 26: a sweep whose last state repeats its first (a closed period) weights it once
            # in the mean. The recording counted it twice; its mean is recomputed here from the
            # recorded positions without the last, which the check below still compares one by one.
            tes = [p["te_arcsec"] for p in want["positions"][:-1] if p["status"] == "success"]
            if tes:
                want_summary["mean_te_arcsec"] = sum(tes) / len(tes)
        for key, value in want_summary.items():
            if isinstance(value, (dict, list)):
                continue  # a stage's blocks: the every-command snapshot (commands.py) compares them
            kind = SUMMARY_KIND.get(key, "other" if isinstance(value, float) else None)
            least = snapshot_cli.stress_floor(want_summary, SOLVE_PATH_FORCE_N) if key == "max_contact_stress_mpa" else 0.0
            m.close(f"{name}: summary {key}", kind, summary.get(key), value, least)
        m.close(f"{name}: positions", None, len(positions), len(want["positions"]))
        for i, (g, w) in enumerate(zip(positions, want["positions"])):
            compare_positions(m, f"{name}: position {i}", g, w)
        return m.lines
    n = len(want["positions"])
    for i in sorted({0, n // 2}):
        w = want["positions"][i]
        _, doc, _ = solve(exe, path, want["solver"], want["kinematics"],
                          ["--set", f"sweep.crank_start_deg={w['crank_deg']!r}", "--set", "sweep.positions=1"])
        if doc is None:
            m.lines.append(f"{name}: position {i} alone: no output")
            continue
        compare_positions(m, f"{name}: position {i} (alone)", condense(doc)[1][0], w)
    return m.lines


def check(exe, cases, snapshot, deck):
    with lzma.open(snapshot, "rt", encoding="utf-8") as f:
        wanted = [r for r in map(json.loads, f) if r["deck"] == deck]
    if not wanted:
        print(f"no run of {deck} in {snapshot}")
        return 1
    with ThreadPoolExecutor(max_workers=1) as pool:
        problems = [line for lines in pool.map(lambda w: check_run(exe, cases, w), wanted) for line in lines]
    return snapshot_cli.report(deck, len(wanted), problems)


if __name__ == "__main__":
    sys.exit(snapshot_cli.main(make, check, __doc__, records_of))
