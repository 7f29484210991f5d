"""Decks from Python values and arrays (docs/python.md): Deck.from_dict and Deck.set write their TOML
with ltca's one deck writer (C++, app::TomlText), a measured trace reaches the reader from memory (no
file), and Result.tables are built from the results, column for column the document's records.
"""
import math
import os
import pathlib
import tempfile

import numpy as np
import pytest

import ltca
from ltca import _ltca

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def _at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def table1():
    import tomllib
    with open(ROOT / "cases/liu2021_table1.toml", "rb") as f:
        return tomllib.load(f)


# --- the deck writer ---

def test_a_string_with_quotes_backslashes_and_unicode_reads_back_as_it_was():
    title = 'a "quoted" C:\\path — Zahnrad ü 歯車 \U0001f527'
    deck = ltca.Deck.load("cases/liu2021_table1.toml").set("case.title", title)
    assert ltca.mesh(deck).json["case"]["title"] == title
    assert ltca.mesh(ltca.Deck.from_dict({**table1(), "case": {"title": title}})).json["case"]["title"] == title


def test_the_written_values_are_toml_of_their_type():
    write = _ltca._toml_set  # Deck.set's text: the override "section.key=value"
    assert write("load.torque_nm", 100) == "load.torque_nm=100"
    assert write("load.torque_nm", 100.0) == "load.torque_nm=100.0"  # a float stays a float
    assert write("load.torque_nm", np.float32(0.5)) == "load.torque_nm=0.5"
    assert write("load.torque_nm", 0.1) == "load.torque_nm=0.1"  # the shortest text that reads back the same
    assert write("load.torque_nm", 1e-300) == "load.torque_nm=1e-300"
    assert write("sweep.positions", np.int64(37)) == "sweep.positions=37"
    assert write("case.title", 'say "hi"\n') == 'case.title="say \\"hi\\"\\n"'
    assert write("tolerances.lost_motion", np.bool_(True)) == "tolerances.lost_motion=true"
    assert write("tolerances.lost_motion", False) == "tolerances.lost_motion=false"
    nested = write("optimise.variables", {"modification.pin_radius_mm": np.array([-0.03, 0.0]), "x": {"y": [1, (2, 3)]}})
    assert nested == 'optimise.variables={ "modification.pin_radius_mm" = [-0.03, 0.0], x = { y = [1, [2, 3]] } }'
    text = _ltca._toml_deck({"load": {"torque_nm": 100.0}, "a b": {"c.d": True}})
    assert text == '[load]\ntorque_nm = 100.0\n\n["a b"]\n"c.d" = true\n\n'
    assert ltca.Deck.load("cases/liu2021_tolerances.toml").set("tolerances.lost_motion", np.bool_(True)).sets[-1] == \
        "tolerances.lost_motion=true"  # read: the deck's limit on lost motion needs it true


def test_nested_tables_and_lists_of_numpy_scalars_read_as_the_file_does():
    file = ltca.Deck.load("cases/liu2021_optimise.toml")
    variables = {"modification.pin_radius_mm": [np.float64(-0.03), np.float32(0.0)],
                 "modification.pin_circle_radius_mm": np.array([-0.03, 0.0])}
    constraints = {"mean_backlash_arcsec": {"min": np.int64(60), "max": 120.0}, "max_contact_stress_mpa": 1500.0}
    deck = file.update({"optimise.variables": variables, "optimise.constraints": constraints, "optimise.maximise": np.bool_(False)})
    a = ltca.optimise(file, evaluations=2, threads=1).json["settings"]
    b = ltca.optimise(deck, evaluations=2, threads=1).json["settings"]
    assert a == b


@pytest.mark.parametrize("value, expected", [
    (None, "expected a bool, number, string, list or table"),
    ({1, 2}, "expected a bool, number, string, list or table"),
    (1 + 2j, "expected a bool, number, string, list or table"),
    ([1.0, None], "expected a bool, number, string, list or table"),
    (2**63, "TOML's 64 bits"),
    (-(2**63) - 1, "TOML's 64 bits"),
    ("\udcff", "UTF-8"),
])
def test_a_value_the_writer_cannot_write_is_a_value_error_naming_the_key(value, expected):
    deck = ltca.Deck.load("cases/liu2021_table1.toml")
    with pytest.raises(ValueError, match="load.torque_nm = ") as e:
        deck.set("load.torque_nm", value)
    assert expected in str(e.value)
    with pytest.raises(ValueError, match=r"load\.extra\.inner = ") as e:
        ltca.Deck.from_dict({**table1(), "load": {"torque_nm": 100.0, "extra": {"inner": value}}})
    assert expected in str(e.value)


def test_a_list_that_holds_itself_or_too_deep_is_refused_naming_the_key_and_a_0d_array_is_its_value():
    loop = [1.0]
    loop.append(loop)
    with pytest.raises(ValueError, match=r"load\.torque_nm = .*nested at most 64 deep"):
        _ltca._toml_set("load.torque_nm", loop)
    deep = 1.0
    for _ in range(70):
        deep = {"x": deep}
    with pytest.raises(ValueError, match=r"optimise\.variables\.x\.x.*nested at most 64 deep"):
        _ltca._toml_set("optimise.variables", deep)
    assert _ltca._toml_set("load.torque_nm", np.array(12.5)) == "load.torque_nm=12.5"
    with pytest.raises(ValueError, match="UTF-8"):
        _ltca._toml_deck({"load": {"\udcff": 1}})


def test_the_largest_integers_are_written_and_the_reader_judges_them():
    assert _ltca._toml_set("sweep.positions", 2**63 - 1) == f"sweep.positions={2**63 - 1}"
    assert _ltca._toml_set("sweep.positions", -(2**63)) == f"sweep.positions={-(2**63)}"
    deck = ltca.Deck.load("cases/liu2021_table1.toml")
    with pytest.raises(ValueError, match="positions"):
        deck.set("sweep.positions", 2**63 - 1)  # beyond [sweep] positions' limit


def test_nan_and_inf_are_written_and_refused_by_the_reader_naming_the_key():
    deck = ltca.Deck.load("cases/liu2021_table1.toml")
    for value in (math.nan, np.float64("inf"), -math.inf):
        with pytest.raises(ValueError, match="torque_nm"):
            deck.set("load.torque_nm", value)
    with pytest.raises(ValueError, match=r"\[section\]: expected a dict of keys, got list"):
        ltca.Deck.from_dict({"section": [1]})


# --- a measured trace from memory ---

def trace():
    with open("cases/data/measured_profile.csv", encoding="utf-8") as f:
        rows = [line for line in f if line.strip() and not line.lstrip().startswith("#")][1:]
    return np.loadtxt(rows, delimiter=",", unpack=True)


def test_a_trace_from_arrays_writes_no_file_and_is_named_in_memory(monkeypatch):
    angle, deviation = trace()

    def no_file(*args, **kwargs):
        raise AssertionError("with_measured_profile wrote a file")
    monkeypatch.setattr(tempfile, "mkdtemp", no_file)
    monkeypatch.setattr(tempfile, "mkstemp", no_file)
    deck = ltca.Deck.load("cases/measured_profile.toml").with_measured_profile(angle, deviation)
    assert deck.sets[-1] == 'errors.profile_measured_csv="<measured profile from Python>"'
    assert ltca.solve(deck).summary["pp_te_arcsec"] == ltca.solve("cases/measured_profile.toml").summary["pp_te_arcsec"]


def test_a_deck_keeps_its_own_trace_and_a_bad_trace_names_the_memory_file_and_line():
    angle, deviation = trace()
    base = ltca.Deck.load("cases/measured_profile.toml")
    a = base.with_measured_profile(angle, deviation)
    b = a.with_measured_profile(angle, 2.0 * deviation)  # replaces a's trace in b only
    pa, pb = ltca.solve(a).summary["pp_te_arcsec"], ltca.solve(b).summary["pp_te_arcsec"]
    assert pa != pb and ltca.solve(a).summary["pp_te_arcsec"] == pa
    assert ltca.solve(a.set("load.torque_nm", 50)).summary["pp_te_arcsec"] != pa  # overrides keep the trace
    bad = deviation.copy()
    bad[2] = np.nan
    with pytest.raises(ValueError, match=r'profile_measured_csv = "<measured profile from Python>": line 4: deviation_um = nan'):
        base.with_measured_profile(angle, bad)


def test_a_deck_file_still_names_its_trace_file():
    with pytest.raises(ValueError, match=r'profile_measured_csv = "data/nope.csv"'):
        ltca.Deck.load("cases/measured_profile.toml").set("errors.profile_measured_csv", "data/nope.csv")


# --- tables from the results ---

def document_table(rows):
    """The reference: a list of the document's records as {key: array} for the keys whose values
    are numbers (None as NaN) or equal-length lists of numbers in every record, as Result.tables
    was built in Python from the document before."""
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    table = {}
    for k in keys:
        values = [r.get(k) for r in rows]
        if all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in values):
            table[k] = np.array([np.nan if v is None else float(v) for v in values], dtype=float)
        elif all(isinstance(v, list) for v in values) and len({len(v) for v in values}) == 1:
            try:
                table[k] = np.array([[np.nan if x is None else float(x) for x in v] for v in values], dtype=float)
            except (TypeError, ValueError):
                pass
    return table


def two_discs_with_friction():
    """cases/rv_two_discs.toml with the [friction] and [operation] of the efficiency case."""
    import tomllib
    with open(ROOT / "cases/jiang2022_table2_efficiency.toml", "rb") as f:
        sections = tomllib.load(f)
    return ltca.Deck.load("cases/rv_two_discs.toml").update(
        {f"{section}.{key}": value for section in ("friction", "operation") for key, value in sections[section].items()})


@pytest.mark.parametrize("run", [
    lambda: ltca.backlash("cases/liu2021_table1.toml"),
    lambda: ltca.backlash("cases/rv_two_discs.toml"),
    lambda: ltca.backlash("cases/hard/law_cannot_carry.toml"),
    lambda: ltca.mesh("cases/liu2021_table1.toml", crank_deg=2),
    lambda: ltca.mesh("cases/liu2021_sec52_base.toml"),
    lambda: ltca.compare("cases/liu2021_table1.toml", solvers=["bisection", "compatibility"]),
    lambda: ltca.compare("cases/rv_two_discs.toml"),
    lambda: ltca.compare("cases/stage/cycloidal_drive.toml", solvers=["bisection", "energy-groups"]),  # one skipped
    lambda: ltca.stiffness("cases/liu2021_table1.toml", steps=5),
    lambda: ltca.stiffness("cases/rv_two_discs.toml", steps=5, crank_deg=1),
    lambda: ltca.stiffness("cases/stage/cycloidal_drive.toml", steps=5, crank_deg=0),
    lambda: ltca.efficiency("cases/jiang2022_table2_efficiency.toml"),
    lambda: ltca.efficiency(two_discs_with_friction()),
    lambda: ltca.optimise("cases/liu2021_optimise.toml", evaluations=4, threads=1),
    lambda: ltca.tolerance("cases/liu2021_tolerances.toml", samples=3, threads=1),
    lambda: ltca.tolerance("cases/jiang2022_tolerances.toml", samples=60, threads=2),  # with the sensitivity rankings
    lambda: ltca.optimise("cases/liu2021_robust.toml", evaluations=2, threads=2),
    lambda: ltca.geometry("cases/liu2021_table1.toml"),
])
def test_tables_are_the_documents_records_column_for_column(run):
    result = run()
    expected = {k: document_table(v) for k, v in result.json.items()
                if isinstance(v, list) and v and all(isinstance(r, dict) for r in v)}
    assert sorted(result.tables) == sorted(expected)
    for name, table in expected.items():
        got = result.tables[name]
        assert list(got) == list(table), name  # the same columns, in the document's (name) order
        for column, values in table.items():
            assert got[column].dtype == np.float64 and got[column].shape == values.shape, (name, column)
            assert np.array_equal(got[column], values, equal_nan=True), (name, column)
        assert result.table(name) is got
    # Every list further in, by table(*path): the same columns as the document's records.
    nested = list(record_lists(result.json))
    for path in nested:
        node = result.json
        for step in path:
            node = node[step]
        got, want = result.table(*path), document_table(node)
        assert list(got) == list(want), path
        for column, values in want.items():
            assert np.array_equal(got[column], values, equal_nan=True), (path, column)
    assert all(p in result._nested or p[0] in result.tables for p in nested)  # every one from the result
    if result.command == "tolerance" and result.json["summary"]["samples"] >= 60:
        assert any(p[-1] == "ranking" for p in nested)


def record_lists(node, path=()):
    """The paths of every non-empty list of records in a document."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from record_lists(v, path + (k,))
    elif isinstance(node, list) and node:
        if all(isinstance(r, dict) for r in node):
            yield path
        for i, v in enumerate(node):
            yield from record_lists(v, path + (i,))


# --- issue 54: --unset from Python ---

def test_unset_takes_a_section_or_a_key_out_as_the_command_line_does():
    stage = ltca.Deck.load("cases/stage/cycloidal_drive.toml").set("sweep.positions", 3)
    mesh = stage.unset("output", "bearing")
    assert "stage" in ltca.solve(stage).json["summary"]
    assert "stage" not in ltca.solve(mesh).json["summary"]
    # the same positions of the mesh alone as the command line's --unset gives
    assert len(ltca.solve(mesh).json["positions"]) == 3
    with pytest.raises(ValueError, match=r"the deck has no \[frction\]"):
        stage.unset("frction")
    with pytest.raises(ValueError, match="has no key 'torq'"):
        stage.unset("load.torq")
    with pytest.raises(ValueError, match="expected section or section.key"):
        stage.unset("load.torque_nm=1")
