"""Issue 30: the Python module gives what the command line gives (docs/python.md).

Run by ctest with LTCA_EXE (the ltca executable) and PYTHONPATH (the build tree's python folder)
set, from the repository's root. The reference for each check is the ltca executable itself:
`ltca solve DECK --json -` in its own process.
"""
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import ltca

LTCA = os.environ.get("LTCA_EXE", "build/release/ltca")
ROOT = pathlib.Path(__file__).resolve().parents[2]
CASES = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "cases").rglob("*.toml"))
TIMING = {"wall_seconds", "loaded_solve_seconds"}  # measured, not computed: differ between runs


def without_timing(doc):
    if isinstance(doc, dict):
        return {k: without_timing(v) for k, v in doc.items() if k not in TIMING}
    if isinstance(doc, list):
        return [without_timing(v) for v in doc]
    return doc


def cli_solve(deck, *args):
    run = subprocess.run([LTCA, "solve", deck, "--json", "-", *args], cwd=ROOT, capture_output=True, text=True)
    return run.returncode, run.stdout, run.stderr


@pytest.mark.parametrize("deck", CASES)
def test_solve_equals_the_command_line_json_to_the_last_digit(deck, monkeypatch):
    monkeypatch.chdir(ROOT)
    code, out, err = cli_solve(deck)
    if code == 2:  # bad input for `ltca solve` (e.g. no [material]): the module says so too
        with pytest.raises(ValueError):
            ltca.solve(ltca.Deck.load(deck))
        return
    assert code in (0, 1), err
    expected = json.loads(out)
    result = ltca.solve(ltca.Deck.load(deck))
    # json.loads reads each double back exactly (the writer prints 17 significant digits): the
    # comparison is exact, with no tolerance.
    assert without_timing(result.json) == without_timing(expected)
    assert result.status == expected["summary"]["status"]
    assert (code == 0) == result.succeeded
    # The arrays are the document's: the crank and the TE of every successful position.
    positions = expected["positions"]
    assert len(result.crank_deg) == len(positions)
    for i, p in enumerate(positions):
        assert result.crank_deg[i] == p["crank_deg"]
        if p["status"] == "success":
            assert result.te_arcsec[i] == p["te_arcsec"]
            assert result.pin_force_n[i].max() == max(p["pin_force_n"])
        else:
            assert math.isnan(result.te_arcsec[i])


def test_solver_and_kinematics_keywords_are_the_command_lines_options(monkeypatch):
    monkeypatch.chdir(ROOT)
    deck = "cases/liu2021_table1.toml"
    code, out, _ = cli_solve(deck, "--solver", "compatibility", "--kinematics", "exact")
    assert code == 0
    result = ltca.solve(deck, solver="compatibility", kinematics="exact")
    assert without_timing(result.json) == without_timing(json.loads(out))
    assert result.json["solver"]["name"] == "compatibility"


def test_set_and_from_dict_read_as_the_deck_file_does(monkeypatch):
    monkeypatch.chdir(ROOT)
    deck = "cases/liu2021_table1.toml"
    code, out, _ = cli_solve(deck, "--set", "load.torque_nm=100", "--set", "modification.pin_circle_radius_mm=-0.01")
    assert code == 0
    d = ltca.Deck.load(deck).set("load.torque_nm", 100).set("modification.pin_circle_radius_mm", -0.01)
    assert without_timing(ltca.solve(d).json) == without_timing(json.loads(out))
    # The same deck as a dict: the figures are the file's (the deck's name differs).
    import tomllib
    with open(deck, "rb") as f:
        sections = tomllib.load(f)
    from_dict = ltca.solve(ltca.Deck.from_dict(sections))
    from_file = ltca.solve(ltca.Deck.load(deck))
    assert without_timing(from_dict.summary) == without_timing(from_file.summary)
    assert np.array_equal(from_dict.pin_force_n, from_file.pin_force_n)


def table1():
    import tomllib
    with open(ROOT / "cases/liu2021_table1.toml", "rb") as f:
        return tomllib.load(f)


@pytest.mark.parametrize("build", [
    lambda: ltca.Deck.load("cases/liu2021_table1.toml").set("pair.pin_cuont", 40),
    lambda: ltca.Deck.load("cases/liu2021_table1.toml").set("pair.pin_count", -3),
    lambda: ltca.Deck.from_dict({**table1(), "load": {"torque_nmm": 5.0}}),
])
def test_bad_input_raises_value_error_naming_the_key(build, monkeypatch):
    monkeypatch.chdir(ROOT)
    with pytest.raises(ValueError) as e:
        build()
    message = str(e.value)
    assert "pin_cuont" in message or "pin_count" in message or "torque_nmm" in message


def test_a_failed_solve_returns_its_status_and_nulls_never_a_number(monkeypatch):
    monkeypatch.chdir(ROOT)
    deck = "cases/hard/law_cannot_carry.toml"
    code, out, _ = cli_solve(deck)
    assert code == 1
    result = ltca.solve(deck)
    assert not result.succeeded
    assert result.status == json.loads(out)["summary"]["status"]

    def no_nan(x):
        if isinstance(x, float):
            return not math.isnan(x)
        if isinstance(x, dict):
            return all(no_nan(v) for v in x.values())
        if isinstance(x, list):
            return all(no_nan(v) for v in x)
        return True
    assert no_nan(result.json)  # JSON's nulls are None, never NaN
    failed = [i for i, p in enumerate(result.json["positions"]) if p["status"] != "success"]
    assert failed and all(result.json["positions"][i]["te_arcsec"] is None for i in failed)
    assert all(math.isnan(result.te_arcsec[i]) for i in failed)


def spectrum_deck(path, bins):
    """cases/stage/cycloidal_drive.toml with a [[load_spectrum]] entry per (torque_nm, speed_rpm,
    time_share), written to path."""
    path.write_text((ROOT / "cases/stage/cycloidal_drive.toml").read_text() + "".join(
        f"\n[[load_spectrum]]\ntorque_nm = {t}\nspeed_rpm = {n}\ntime_share = {s}\n" for t, n, s in bins))
    return path


def test_a_load_spectrum_is_in_the_document_as_the_command_line_writes_it(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    deck = spectrum_deck(tmp_path / "spectrum.toml", [(150, 1000, 0.25), (206, 1500, 0.75)])
    code, out, err = cli_solve(str(deck), "--set", "sweep.positions=12", "--set", "sweep.crank_end_deg=330")
    assert code == 0, err
    expected = json.loads(out)
    result = ltca.solve(ltca.Deck.load(str(deck)).update({"sweep.positions": 12, "sweep.crank_end_deg": 330}))
    assert "spectrum" in result.json
    assert without_timing(result.json["spectrum"]) == without_timing(expected["spectrum"])


def test_a_failed_load_spectrum_bin_is_not_a_success(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    deck = spectrum_deck(tmp_path / "spectrum_fails.toml", [(206, 1500, 0.5), (200000, 1500, 0.5)])
    code, _, err = cli_solve(str(deck), "--set", "sweep.positions=4", "--set", "sweep.crank_end_deg=270")
    assert code == 1, err  # the second bin's law cannot carry 200,000 N*m
    result = ltca.solve(ltca.Deck.load(str(deck)).update({"sweep.positions": 4, "sweep.crank_end_deg": 270}))
    assert result.status == "success"  # the deck's own sweep
    assert not result.spectrum_succeeded
    assert not result.succeeded
