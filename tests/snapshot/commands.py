#!/usr/bin/env python3
"""Snapshot of every ltca command on every deck before the issue-24 refactoring, and its check.

    commands.py make  LTCA CASES OUT.jsonl          # record (then: xz -9 OUT.jsonl)
    commands.py check LTCA CASES SNAPSHOT.jsonl.xz DECK
    commands.py remake LTCA CASES OLD.jsonl.xz OUT.jsonl DECK...   # re-record DECKs only (then: xz -9)

`make` runs, for every deck in CASES (ltca's working directory is CASES and the deck is given
relative to it, so `case.deck` and messages read the same wherever the tree is):

    geometry; mesh --crank-deg 0; backlash --kinematics K; solve --solver S --kinematics K;
    compare --solvers (all four) --kinematics K; stiffness --crank-deg 0;
    efficiency (a deck with [friction] and [operation]);
    tolerance --samples 20 --threads 1 (a deck with [tolerances]; the worst case is kept);
    report -o DIR (with --set tolerances.samples=20 on a deck with [tolerances]), reading back
    the JSON documents it leaves in DIR;

for S in bisection, energy-qp, energy-groups, compatibility and K in linearised, exact. Every
command but report writes `--json -`. One JSON line per run: deck, command, args (after the
deck), exit code, the seconds it took (`generated_wall_seconds`, never compared), and `json`:
the document with every field of TIMING dropped (at any depth), or for report {file: document}.
A run that fails (exit 2: the command does not apply, e.g. a deck without [material]; or no
JSON at all) keeps the last line of its standard error as `message` (report keeps the documents
it wrote before failing too). Python writes a float as the shortest text
that reads back to the same double.

The documents drop some bulky per-position arrays (PER_POSITION_DROPPED, the reasons beside it).

Sampling: a run that took more than SAMPLE_SECONDS is kept in the file (`checked` false) with
its exit code and summary only, and recorded again at its sweep's first crank angle, and its middle one unless the first alone took
more than SAMPLE_SECONDS, each run alone with
`--set sweep.crank_start_deg=C --set sweep.positions=1` (`checked` true, `sampled_from` naming
the whole run's args). The crank angles are the deck's sweep as its linearised backlash gives it
back. Runs with Li's tooth groups (solve --solver energy-groups, and compare) on the 160- and
320-pin scaling decks (TOO_SLOW_WHOLE: 70 s and 800 s per sweep) are recorded so, never whole.
Stiffness at crank 0 has no sweep to sample and is always checked whole. `check` runs only the checked records.

`check` re-runs one deck's records and compares: exit codes, strings, booleans, nulls, integers,
object keys and array lengths exactly; every float to RELATIVE (1e-12) relative, or, near zero,
to an absolute floor by the field's unit: ABSOLUTE_BY_SUFFIX (1e-9 in arcsec, arcmin, um, mm,
deg, MPa), 1e-12 otherwise (N, N*m, J, W, efficiencies, residuals). An array element takes the
floor of the field that holds the array. Prints the mismatches; exit 1 on any.

It is a regression anchor, not a validation: it records what the code computed at the commit
named in tests/snapshot/README.md, so that a refactoring can show it changed no number.
"""
import json
import re
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
TOLERANCE_SAMPLES = "20"
SAMPLE_SECONDS = 0.5
RELATIVE = 1e-12
ABSOLUTE_DEFAULT = 1e-12
ABSOLUTE_BY_SUFFIX = {"_arcsec": 1e-9, "_arcmin": 1e-9, "_um": 1e-9, "_mm": 1e-9, "_deg": 1e-9,
                      "_mpa": 1e-9}
# Fields that measure time or the machine, dropped at any depth (found by reading every command's
# output): wall_seconds (summaries, compare's solvers, tolerance's worst_case),
# loaded_solve_seconds (efficiency), samples_per_second (tolerance), threads and mpi_ranks
# (tolerance: its samples do not depend on them).
# Per-position arrays dropped to keep the file small (2.3 MB instead of 10 MB with xz -9):
# pin_angle_deg (the kinematics of the pins; mesh keeps them at crank 0), clearance_um and
# clearance_at_first_contact_um (backlash's per-pin gaps; theta_c1, theta_c2, backlash and the
# first-contact pins are kept, and mesh keeps clearance_um at crank 0), contact_stress_mpa and
# slice_stress_mpa (Hertz of the pin and slice forces, which are kept, as is the summary's
# max_contact_stress_mpa).
PER_POSITION_DROPPED = {"pin_angle_deg", "clearance_um", "clearance_at_first_contact_um",
                        "contact_stress_mpa", "slice_stress_mpa"}
TOO_SLOW_WHOLE = {"scaling/zp160.toml", "scaling/zp320.toml"}
TIMING = {"wall_seconds", "loaded_solve_seconds", "samples_per_second", "threads", "mpi_ranks"}
# Issue 27: since the stiffness loop's torque balance with friction starts where the same balance
# ended at the previous crank angle, and its first step takes the residual's slope -(1 + r) instead
# of -1, it reaches the same fixed point along another path, to its tolerance (1e-10 of T in the
# torque the normal forces carry). In the runs that solve that loop (stiffness and report of a
# deck with [friction]) floats are compared to FRICTION_LOOP_RELATIVE, which covers that tolerance
# through the rigidity's secant (measured: 2.3e-10 on jiang2022_table2_efficiency.toml), and the
# count of solves, which the change lowered, is not compared.
FRICTION_LOOP_COMMANDS = {"stiffness", "report", "tolerance"}
FRICTION_LOOP_RELATIVE = 1e-8
FRICTION_LOOP_UNCOMPARED = {"solves"}
# Issue 29: the law inversion (Halley's method on F from a warm start, where Newton on ln F ran to
# 1e-15), the compatibility solver's reuse of its last evaluation and the mesh state's pose and pin
# centres computed once change the last bits of a force, and a solver's stopping decisions follow
# another path inside the band its torque tolerance allows (1e-10 of T). The commands that solve
# loads (SOLVE_PATH_COMMANDS) are compared to SOLVE_PATH_RELATIVE with SOLVE_PATH_ABSOLUTE as the
# least floor of any field, and SOLVE_PATH_FORCE_N of a force (a field ending in _n): the band
# moves a small force by up to about 1e-10 of the torque over the pin-circle radius (3.2e-7 N at
# 206 N*m on 64 mm). The counts of evaluations and iterations are not compared, and the numbers
# inside messages are masked (their words are compared). Measured at the change: the largest
# absolute difference 1.1e-7 N (2.0e-11 of a 5,352 N force), 3.3e-8 N on a 0.98 N force; statuses,
# exit codes and array lengths unchanged. The commands that solve no load (geometry, mesh,
# backlash) keep 1e-12.
SOLVE_PATH_COMMANDS = {"solve", "compare", "stiffness", "report", "tolerance", "efficiency"}
SOLVE_PATH_RELATIVE = 1e-8
SOLVE_PATH_ABSOLUTE = 1e-8
SOLVE_PATH_FORCE_N = 1e-6
SOLVE_PATH_UNCOMPARED = {"torque_evaluations", "iterations", "solves"}

NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


# Whether bisection's last miss falls just inside the torque tolerance or inside the band below it
# that double precision cannot resolve is a stopping decision on the path like the counts: both are
# a success, the second says so in a note, which is not compared (issue 29: the exact kinematics'
# trials skip the foot-point search of pins that cannot have closed, so their warm starts, and the
# last bits of each trial's torque, differ).
PATH_NOTES = (" (limited by the resolution of the rotation in double precision)",)


# Issue 29: under exact kinematics the compatibility solver closes the exact torque balance by
# Newton's method from the solution of the linearisation about the unloaded pose, where it
# re-linearised and minimised again until the rotation settled; its message names the new
# iteration. Same figures (compared as above), same statuses; the words of the old message are
# what the recording holds.
REWORDED = {
    # The refusal of a solver that does not solve the reducer stage lists the solvers that do from
    # the registry (solvers::ReducerSolverNames, registry order) where a hand-written list had them in
    # another order: same solvers, same words.
    'solver "energy-groups" does not solve the reducer stage ([output]); solvers that do: bisection, energy-qp, '
    'compatibility (docs/stage.md)':
        'solver "energy-groups" does not solve the reducer stage ([output]); solvers that do: compatibility, bisection, '
        'energy-qp (docs/stage.md)',
    "exact torque balance: linearisations #, Newton steps #, torque balanced to #":
        "# re-linearisations, torque balanced to #",
    "iteration limit reached (linearisations #, Newton steps #) before the torque balanced: off by # relative at "
    "the stop, torque_tolerance #":
        "iteration limit reached (# re-linearisations) before the torque balanced: off by # relative at the stop, "
        "torque_tolerance #",
}


# Fields a document gained after the recording, compared nowhere (an "extra" key of these names is
# not a difference; a missing one still is): the geometry document's inspection figures, root and
# tip diameters and the dimension over rollers (docs/export.md), checked against their own
# derivation by tests/geometry/inspection_test.cpp; and (issue 53) the band of the dimension over
# rollers from [tolerances] and the deviation chart of a measured trace, checked by
# tests/analysis/roller_tolerance_test.cpp and tests/geometry/deviation_fit_test.cpp.
# Issue 50: a stage's bearings' load-zone life, static safety and roller stress (docs/stage.md),
# checked against their own derivations (tests/contact/bearing_test.cpp,
# docs/derivations/load_zone_life.py).
# Issue 49: a stage's model block names its scope (what is elastic, what rigid), and its strain
# energy and compliance budget the carrier in series (zero for the recorded decks, whose carriers are
# rigid; tests/app/stage_as_built_test.cpp).
# Issue 54: a sweep's notes (too few positions a mesh period), checked by tests/app/deck_test.cpp;
# the tolerance document's percentile_rule (below, tolerance_statistics_as_recorded).
# Issue 50: a sweep's pitting rating of the pins and teeth (contact_fatigue), checked by
# tests/app/contact_fatigue_test.cpp against a recount from the positions' pressures.
ADDED = {"contact_fatigue", "root_diameter_mm", "tip_diameter_mm", "dimension_over_rollers_mm", "over_rollers",
         "dimension_over_rollers_tolerance", "profile_deviation_chart",
         "turning_raceway", "turning_raceway_basis", "load_zone_equivalent_load_n", "load_zone_life_million_revolutions",
         "load_zone_life_hours", "load_zone_to_basic_life_ratio", "shortest_load_zone_life_hours", "max_bearing_load_per_bearing_n", "static_safety",
         "smallest_static_safety", "max_roller_contact_stress_mpa", "largest_roller_contact_stress_mpa",
         "roller_contact_stress_limit_mpa", "verdicts", "notes", "scope", "carrier", "support_bearings",
         # Issue 52: a preloaded pair's figures (null or 0 for the recorded decks, which have free
         # play everywhere; tests/solvers/preload_test.cpp, tests/analysis/preload_test.cpp).
         "preload", "preloaded_positions", "cannot_assemble_positions", "max_preload_force_n",
         "max_preload_stress_mpa", "interference_arcsec", "unload_torque_nm", "unload_torque_reverse_nm",
         "max_interference_arcsec", "min_unload_torque_nm", "cannot_assemble", "preloaded", "preloaded_share",
         "preload_max_contact_stress_mpa", "preload_max_force_n",
         "percentile_rule",
         # A deck read with --set or --unset names them in its case (the report's runs here).
         "overrides"}
# Issue 51: efficiency's loss by source, the stage's friction moment bound and the new [friction]
# keys in its head (docs/efficiency.md), checked by tests/app/stage_efficiency_test.cpp.
ADDED |= {"power_loss_by_source_w", "stage_friction_moment_ratio", "stage_friction_moment_ratio_min",
          "stage_friction_moment_ratio_max", "limiting_shear_stress_coefficient", "limiting_shear_stress_mpa",
          "output_pin_coefficient", "bearing_coefficient", "bearing_diameter_mm"}


# Issue 46: `ltca compare` of a reducer stage ([output]) lists a solver that does not solve the stage
# as skipped, with its reason, instead of running it into status stage-unsupported, and its exit
# code judges the solvers that ran. The recording (52e18cf) has such a solver among `solvers` with
# that status and the run's exit 1: it is read as the skipped entry it now is, and the exit as
# what the solvers that ran give. Every figure of the solvers that ran is compared as before.
STAGE_SKIP_REASON = "does not solve the reducer stage ([output]; docs/stage.md)"


def skipped_as_now(want):
    """The recorded run as issue 46 writes it: `compare` of a stage (see STAGE_SKIP_REASON), and a
    `report` that failed (exit 2 or more), which now leaves no file where the recording read the
    documents its parts had written before the failure (all or nothing)."""
    if want["command"] == "report" and want["exit"] >= 2 and want.get("json") is not None:
        want = dict(want)
        want["json"] = None
        return want
    doc = want.get("json")
    if want["command"] != "compare" or not isinstance(doc, dict):
        return want
    unsupported = [x for x in doc.get("solvers", []) if x.get("status") == "stage-unsupported"]
    if not unsupported:
        return want
    want = dict(want)
    doc = dict(doc)
    doc["solvers"] = [x for x in doc["solvers"] if x.get("status") != "stage-unsupported"]
    doc["skipped"] = [{"name": x["name"], "reason": STAGE_SKIP_REASON} for x in unsupported]
    want["json"] = doc
    if want["exit"] == 1 and all(x.get("failed_positions") == 0 for x in doc["solvers"]):
        want["exit"] = 0
    return want


# Issue 46: a balance that the arithmetic cannot resolve (a torque so small that its rotation is
# below what the exact geometry resolves in double precision: hard/tiny_torque.toml under exact
# kinematics) now carries a warning that says so, where it was a plain success. The recording
# predates that warning: it is left out of what the program gives before the comparison (from each
# position's warnings, and a summary's first warning and warned count where the recording had none).
RESOLUTION_WARNING = "resolution-limited balance"


def without_resolution_warnings(got, want):
    if isinstance(got, dict) and isinstance(want, dict):
        got = dict(got)
        if isinstance(got.get("warnings"), list):
            got["warnings"] = [w for w in got["warnings"] if RESOLUTION_WARNING not in w]
        first = got.get("first_warning")
        if isinstance(first, str) and RESOLUTION_WARNING in first and want.get("first_warning") is None:
            if "first_warning" in want:
                got["first_warning"] = None
            else:
                del got["first_warning"]
            got["warned_positions"] = want.get("warned_positions", 0)
        for k in got:
            if k in want:
                got[k] = without_resolution_warnings(got[k], want[k])
        return got
    if isinstance(got, list) and isinstance(want, list):
        return [without_resolution_warnings(g, w) for g, w in zip(got, want)] + got[len(want):]
    return got


# Issue 54, tolerance statistics. (1) A percentile is given only where the count supports it,
# count x min(p, 1 - p) >= 1 (analysis::kPercentileRule): the recorded runs have 20 samples, so p1
# and p99 are null now; the recorded value of such a percentile is read as null (tested against the
# rule by tests/app/tolerance_test.cpp), every other percentile compared as before. (2) A key's
# share is Pratt's SRC x r summed over its columns, which adds up to R^2; the recording's share was
# the sum of SRC^2, which the document keeps as src_squared: the recorded share is compared with
# src_squared, the ranking in its order (largest first), and the new share (tested to add up to R^2)
# nowhere; the method's text, which now names Pratt's measure, is read as the recording's.
PERCENTILES = {"p1": 1, "p5": 5, "p50": 50, "p95": 95, "p99": 99}


def tolerance_statistics_as_recorded(got, want):
    """(got, want) with the two changes above undone in got and the unsupported percentiles nulled
    in want."""
    if isinstance(got, dict) and isinstance(want, dict):
        got, want = dict(got), dict(want)
        if "count" in want and "p50" in want and isinstance(want.get("count"), int):
            for key, percent in PERCENTILES.items():
                if key in want and want["count"] * min(percent, 100 - percent) < 100:
                    want[key] = None
        ranking = got.get("ranking")
        if isinstance(ranking, list) and all(isinstance(k, dict) and "src_squared" in k for k in ranking):
            entries = []
            for k in ranking:
                k = dict(k)
                k["share"] = k.pop("src_squared")
                entries.append(k)
            got["ranking"] = sorted(entries, key=lambda k: -(k["share"] if isinstance(k["share"], float) else 0.0))
        if isinstance(got.get("method"), str) and "Pratt" in got["method"] and isinstance(want.get("method"), str):
            got["method"] = want["method"]
        for k in list(got):
            if k in want:
                got[k], want[k] = tolerance_statistics_as_recorded(got[k], want[k])
        return got, want
    if isinstance(got, list) and isinstance(want, list):
        pairs = [tolerance_statistics_as_recorded(g, w) for g, w in zip(got, want)]
        return [g for g, _ in pairs] + got[len(want):], [w for _, w in pairs] + want[len(got):]
    return got, want


def masked(text):
    """A message with its numbers replaced by '#' and its path notes dropped: its words (a message
    reworded since the recording: the words it had)."""
    if not isinstance(text, str):
        return text
    for note in PATH_NOTES:
        text = text.replace(note, "")
    text = NUMBER.sub("#", text)
    return REWORDED.get(text, text)


def deck_sections(path):
    with open(path, encoding="utf-8") as f:
        return {line.strip().split("]")[0] + "]" for line in f if line.lstrip().startswith("[")}


def runs_of(cases, deck):
    """The (command, args) of one deck, args after the deck."""
    sections = deck_sections(os.path.join(cases, deck))
    runs = [("geometry", []), ("mesh", ["--crank-deg", "0"])]
    runs += [("backlash", ["--kinematics", k]) for k in KINEMATICS]
    runs += [("solve", ["--solver", s, "--kinematics", k]) for s in SOLVERS for k in KINEMATICS]
    runs += [("compare", ["--solvers", ",".join(SOLVERS), "--kinematics", k]) for k in KINEMATICS]
    runs.append(("stiffness", ["--crank-deg", "0"]))
    if "[friction]" in sections and "[operation]" in sections:
        runs.append(("efficiency", []))
    if "[tolerances]" in sections:
        runs.append(("tolerance", ["--samples", TOLERANCE_SAMPLES, "--threads", "1"]))
        runs.append(("report", ["--set", f"tolerances.samples={TOLERANCE_SAMPLES}"]))
    else:
        runs.append(("report", []))
    return runs


def too_slow_whole(deck, command, args):
    """Li's tooth groups on the 160- and 320-pin scaling decks (70 s and 800 s per sweep at
    9dfef0e): recorded at their sampled positions only, never whole."""
    return deck in TOO_SLOW_WHOLE and command in ("solve", "compare") and "energy-groups" in ",".join(args)


def strip(doc, position=False):
    """doc without TIMING (any depth) and, in an element of a positions array, PER_POSITION_DROPPED."""
    if isinstance(doc, dict):
        return {k: strip(v, k == "positions") for k, v in doc.items()
                if k not in TIMING and not (position and k in PER_POSITION_DROPPED)}
    if isinstance(doc, list):
        return [strip(v, position) for v in doc]
    return doc


def run(exe, cases, deck, command, args):
    """Runs one command; returns (exit code, stripped JSON or None, message or None, seconds)."""
    with tempfile.TemporaryDirectory() as tmp:
        argv = [exe, command, deck, *args]
        argv += ["-o", tmp] if command == "report" else ["--json", "-"]
        start = time.monotonic()
        proc = subprocess.run(argv, cwd=cases, capture_output=True, text=True, check=False)
        wall = time.monotonic() - start
        doc = None
        if command == "report":
            files = sorted(f for f in os.listdir(tmp) if f.endswith(".json"))
            if files:
                doc = {}
                for name in files:
                    with open(os.path.join(tmp, name), encoding="utf-8") as f:
                        doc[name] = strip(json.load(f))
        elif proc.stdout.strip():
            doc = strip(json.loads(proc.stdout))
        message = None
        if doc is None or proc.returncode >= 2:
            lines = [line for line in proc.stderr.splitlines() if line.strip()]
            message = lines[-1] if lines else ""
        return proc.returncode, doc, message, wall


def record(exe, cases, deck, command, args, checked=True, sampled_from=None):
    code, doc, message, wall = run(exe, cases, deck, command, args)
    r = {"deck": deck, "command": command, "args": args, "exit": code, "checked": checked,
         "generated_wall_seconds": round(wall, 2)}
    if sampled_from is not None:
        r["sampled_from"] = sampled_from
    if doc is not None:
        r["json"] = doc
    if message is not None:
        r["message"] = message
    return r


def sweep_cranks(records, deck):
    """The deck's crank angles, as its linearised backlash gives them back (None: no positions)."""
    for r in records:
        if r["deck"] == deck and r["command"] == "backlash" and r["args"][-1] == "linearised":
            positions = (r.get("json") or {}).get("positions") or []
            return [p["crank_deg"] for p in positions] or None
    return None


def add_samples(exe, cases, records, every):
    """Samples the slow runs of records (whole runs) and the runs of every too slow to run whole:
    the slow whole run keeps its exit code and summary only, unchecked; its first position is
    recorded alone, and its middle one too unless the first alone took more than SAMPLE_SECONDS.
    Stiffness at one crank has no sweep to sample: it is checked whole. Returns the samples."""
    slow = [(r["deck"], r["command"], r["args"], r) for r in records
            if r["generated_wall_seconds"] > SAMPLE_SECONDS
            and r["command"] not in ("geometry", "mesh", "stiffness")]
    slow += [(*j, None) for j in every if too_slow_whole(*j)]

    def sample(job):
        deck, command, args, r = job
        cranks = sweep_cranks(records, deck)
        if cranks is None:
            return []
        if r is not None:
            r["checked"] = False
            summary = (r.pop("json", None) or {}).get("summary") if command != "report" else None
            if summary is not None:
                r["summary"] = summary
        out = []
        for c in [cranks[0], cranks[len(cranks) // 2]][:1 if len(cranks) == 1 else 2]:
            sampled = [*args, "--set", f"sweep.crank_start_deg={c!r}", "--set", "sweep.positions=1"]
            out.append(record(exe, cases, deck, command, sampled, True, args))
            if out[0]["generated_wall_seconds"] > SAMPLE_SECONDS:
                break
        return out

    with ThreadPoolExecutor(max_workers=2) as pool:
        return [s for samples in pool.map(sample, slow) for s in samples]


def records_of(exe, cases, decks):
    """Every run of `decks` (the whole runs, then the samples of the slow ones), sorted by deck."""
    every = [(d, c, a) for d in decks for c, a in runs_of(cases, d)]
    jobs = [j for j in every if not too_slow_whole(*j)]
    with ThreadPoolExecutor(max_workers=2) as pool:
        records = list(pool.map(lambda j: record(exe, cases, *j), jobs))
    records += add_samples(exe, cases, records, every)
    records.sort(key=lambda r: r["deck"])
    return records


def make(exe, cases, out):
    exe = os.path.abspath(exe)
    start = time.monotonic()
    decks = sorted(os.path.relpath(os.path.join(d, f), cases)
                   for d, _, files in os.walk(cases) for f in files if f.endswith(".toml"))
    write(records_of(exe, cases, decks), out, len(decks))
    print(f"recording took {time.monotonic() - start:.1f} s")


def write(records, out, decks):
    records.sort(key=lambda r: r["deck"])
    with open(out, "w", encoding="utf-8") as f:
        for r in records:
            f.write(json.dumps(r, sort_keys=True, separators=(",", ":")) + "\n")
    sampled = sum(1 for r in records if "sampled_from" in r)
    slow = [r for r in records if r["checked"] and r["generated_wall_seconds"] > SAMPLE_SECONDS]
    print(f"{decks} decks, {len(records)} runs ({sampled} of them one position of a slow run) -> {out}")
    print(f"checked runs took {sum(r['generated_wall_seconds'] for r in records if r['checked']):.1f} s "
          f"({len(slow)} still over {SAMPLE_SECONDS} s)")


def floor_of(key):
    for suffix, value in ABSOLUTE_BY_SUFFIX.items():
        if key.endswith(suffix):
            return value
    return ABSOLUTE_DEFAULT


def compare(problems, where, key, got, want, relative=RELATIVE, uncompared=frozenset(), floor=0.0):
    """Appends to problems every difference between got and want (key: the field's name); floats to
    `relative` (or the larger of the field's absolute floor and `floor`), keys in `uncompared`
    skipped; with a floor (the solve-path rule), the numbers inside a message are masked."""
    if isinstance(want, dict):
        if not isinstance(got, dict):
            problems.append(f"{where}: {type(got).__name__} != object")
            return
        for k in sorted(set(got) | set(want)):
            if k in uncompared:
                continue
            if k not in want and k in ADDED:
                continue
            if k not in want or k not in got:
                problems.append(f"{where}.{k}: {'extra' if k not in want else 'missing'}")
            else:
                least = floor
                if floor > 0.0 and k == "max_contact_stress_mpa":  # the solve-path rule: its force's floor
                    least = max(floor, snapshot_cli.stress_floor(want, SOLVE_PATH_FORCE_N))
                compare(problems, f"{where}.{k}", k, got[k], want[k], relative, uncompared, least)
        return
    if isinstance(want, list):
        if not isinstance(got, list) or len(got) != len(want):
            problems.append(f"{where}: length {len(got) if isinstance(got, list) else got!r} != {len(want)}")
            return
        for i, (g, w) in enumerate(zip(got, want)):
            compare(problems, f"{where}[{i}]", key, g, w, relative, uncompared, floor)
        return
    number = (int, float)
    if (isinstance(want, float) and isinstance(got, number) and not isinstance(got, bool)) or \
       (isinstance(got, float) and isinstance(want, number) and not isinstance(want, bool)):
        least = floor if floor == 0.0 or not key.endswith("_n") else max(floor, SOLVE_PATH_FORCE_N)
        if abs(got - want) > max(relative * abs(want), floor_of(key), least):
            problems.append(f"{where}: {got!r} != {want!r} (diff {abs(got - want):.3g})")
        return
    if floor > 0.0 and key in ("message", "messages", "warnings") and isinstance(want, str):
        got, want = masked(got), masked(want)
    if type(got) is not type(want) or got != want:
        problems.append(f"{where}: {got!r} != {want!r}")


def check_run(exe, cases, want):
    want = skipped_as_now(want)
    name = f"{want['command']} {want['deck']} {' '.join(want['args'])}"
    code, doc, message, _ = run(exe, cases, want["deck"], want["command"], want["args"])
    problems = []
    loose = want["command"] in FRICTION_LOOP_COMMANDS and "[friction]" in deck_sections(os.path.join(cases, want["deck"]))
    compare(problems, f"{name}: exit", "exit", code, want["exit"])
    path = want["command"] in SOLVE_PATH_COMMANDS
    relative = max(FRICTION_LOOP_RELATIVE if loose else RELATIVE, SOLVE_PATH_RELATIVE if path else RELATIVE)
    uncompared = (FRICTION_LOOP_UNCOMPARED if loose else frozenset()) | (SOLVE_PATH_UNCOMPARED if path else frozenset())
    floor = SOLVE_PATH_ABSOLUTE if path else 0.0
    doc = without_resolution_warnings(doc, want.get("json"))
    wanted = want.get("json")
    if want["command"] in ("tolerance", "report"):
        doc, wanted = tolerance_statistics_as_recorded(doc, wanted)
    compare(problems, f"{name}: json", "json", doc, wanted, relative, uncompared, floor)
    compare(problems, f"{name}: message", "message", message, want.get("message"), RELATIVE, frozenset(), floor)
    return problems


def check(exe, cases, snapshot, deck):
    exe = os.path.abspath(exe)
    with lzma.open(snapshot, "rt", encoding="utf-8") as f:
        tag = '"deck":' + json.dumps(deck) + ","  # parse only this deck's lines (sort_keys, no spaces)
        wanted = [r for r in (json.loads(line) for line in f if tag in line) if r["deck"] == deck and r["checked"]]
    if not wanted:
        print(f"no run of {deck} in {snapshot}")
        return 1
    start = time.monotonic()
    problems = [line for w in wanted for line in check_run(exe, cases, w)]
    return snapshot_cli.report(deck, len(wanted), problems, time.monotonic() - start)


if __name__ == "__main__":
    sys.exit(snapshot_cli.main(make, check, __doc__, records_of))
