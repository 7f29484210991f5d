"""Issue 30: each analysis of the module gives its command's document (docs/python.md).

The reference is the ltca executable: `ltca COMMAND DECK --json -` in its own process, with the
same options. Timings (measured, not computed) are left out of the comparison; everything else is
compared exactly.
"""
import json
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import ltca

LTCA = os.environ.get("LTCA_EXE", "build/release/ltca")
ROOT = pathlib.Path(__file__).resolve().parents[2]
TIMING = re.compile(r"(seconds|_us|_ms|samples_per_second|estimate)$")


def without_timing(doc):
    if isinstance(doc, dict):
        return {k: without_timing(v) for k, v in doc.items() if not TIMING.search(k)}
    if isinstance(doc, list):
        return [without_timing(v) for v in doc]
    return doc


def cli(command, deck, *args):
    run = subprocess.run([LTCA, command, deck, "--json", "-", *args], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode in (0, 1), run.stderr
    return run.returncode, json.loads(run.stdout)


CASES = [
    ("geometry", "cases/liu2021_table1.toml", [], {}),
    ("geometry", "cases/chen2008/d2.toml", ["--crank-deg", "3"], {"crank_deg": 3}),
    ("backlash", "cases/liu2021_table1.toml", [], {}),
    ("backlash", "cases/rv_two_discs.toml", ["--kinematics", "exact"], {"kinematics": "exact"}),
    ("mesh", "cases/liu2021_table1.toml", ["--crank-deg", "2.5"], {"crank_deg": 2.5}),
    ("compare", "cases/liu2021_table1.toml", ["--solvers", "bisection,compatibility"], {"solvers": ["bisection", "compatibility"]}),
    ("stiffness", "cases/liu2021_sec52_base.toml", ["--crank-deg", "0", "--steps", "5"], {"crank_deg": 0, "steps": 5}),
    ("efficiency", "cases/jiang2022_table2_efficiency.toml", [], {}),
    ("tolerance", "cases/jiang2022_tolerances.toml", ["--samples", "12", "--threads", "1", "--no-worst-case"],
     {"samples": 12, "threads": 1, "no_worst_case": True}),
    ("optimise", "cases/liu2021_optimise.toml", ["--evaluations", "15", "--threads", "1"], {"evaluations": 15, "threads": 1}),
]


@pytest.mark.parametrize("command,deck,args,kwargs", CASES, ids=[f"{c[0]}-{pathlib.Path(c[1]).stem}" for c in CASES])
def test_an_analysis_gives_its_commands_json(command, deck, args, kwargs, monkeypatch):
    monkeypatch.chdir(ROOT)
    code, expected = cli(command, deck, *args)
    result = getattr(ltca, command)(ltca.Deck.load(deck), **kwargs)
    assert without_timing(result.json) == without_timing(expected)
    assert result.exit_code == code


def test_tolerance_samples_are_the_csv_of_the_command_line(monkeypatch):
    monkeypatch.chdir(ROOT)
    deck = "cases/jiang2022_tolerances.toml"
    run = subprocess.run([LTCA, "tolerance", deck, "--samples", "12", "--threads", "1", "--no-worst-case", "--csv", "-"], cwd=ROOT,
                         capture_output=True, text=True)
    header, *rows = [line.split(",") for line in run.stdout.strip().splitlines()]
    result = ltca.tolerance(deck, samples=12, threads=1, no_worst_case=True)
    assert list(result.csv) == header
    assert len(result.csv["sample"]) == 12
    for i, name in enumerate(header):
        column = result.csv[name]
        if isinstance(column, np.ndarray):
            assert np.array_equal(column, np.array([float(r[i]) if r[i] else np.nan for r in rows]), equal_nan=True)


def test_geometry_profile_columns_are_the_csv_of_the_command_line(monkeypatch):
    # The module's columns are built from the profile (no CSV parsed); the command's CSV prints the
    # same points to 9 significant digits, so the numbers agree to that rounding and the part
    # names exactly (an empty u_deg, a tip relief's cap, is NaN in the module).
    monkeypatch.chdir(ROOT)
    relief = {"modification.tip_rounding_radius_mm": 1.0}  # a d = 2 profile with rounded tips: caps without u
    for deck, sets in (("cases/liu2021_table1.toml", {}), ("cases/li_table1.toml", {}), ("cases/hard/d2_loaded.toml", relief)):
        args = [a for k, v in sets.items() for a in ("--set", f"{k}={v!r}")]
        run = subprocess.run([LTCA, "geometry", deck, "--csv", "-"] + args, cwd=ROOT, capture_output=True, text=True)
        assert run.returncode == 0
        header, *rows = [line.split(",") for line in run.stdout.strip().splitlines()]
        assert not sets or any(r[1] == "" for r in rows)  # the relieved deck has caps
        result = ltca.geometry(ltca.Deck.load(deck).update(sets) if sets else deck)
        assert list(result.csv) == header
        for i, name in enumerate(header):
            column = result.csv[name]
            if name == "part":
                assert column == [r[i] for r in rows]
                continue
            expected = np.array([float(r[i]) if r[i] else np.nan for r in rows])
            assert np.allclose(column, expected, rtol=1e-8, atol=1e-12, equal_nan=True), name


def test_tables_hold_the_documents_records_as_arrays(monkeypatch):
    monkeypatch.chdir(ROOT)
    result = ltca.backlash("cases/liu2021_table1.toml")
    positions = result.json["positions"]
    table = result.tables["positions"]
    assert table["crank_deg"].shape == (len(positions),)
    assert list(table["crank_deg"]) == [p["crank_deg"] for p in positions]


def test_bad_options_raise_value_error_naming_them(monkeypatch):
    monkeypatch.chdir(ROOT)
    with pytest.raises(ValueError, match="kinematics"):
        ltca.backlash("cases/liu2021_table1.toml", kinematics="exactly")
    with pytest.raises(ValueError, match="optimise"):
        ltca.optimise("cases/liu2021_table1.toml")  # no [optimise]


def test_the_stiffness_curve_is_a_table_of_arrays(monkeypatch):
    monkeypatch.chdir(ROOT)
    result = ltca.stiffness("cases/liu2021_sec52_base.toml", crank_deg=0, steps=5)
    curve = result.json["positions"][0]["curve"]
    table = result.table("positions", 0, "curve")
    assert table and all(len(column) == len(curve) for column in table.values())
    key = next(iter(table))
    assert [r.get(key) for r in curve] == [None if np.isnan(v) else v for v in table[key]]
    # A negative index counts from the end, as the document's list takes it.
    last = result.table("positions", -1, "curve")
    assert sorted(last) == sorted(result.table("positions", len(result.json["positions"]) - 1, "curve"))
    assert all(np.array_equal(last[k], table[k], equal_nan=True) for k in table)  # one crank: -1 is 0
