"""Issue 30: the examples of docs/python.md run, a measured profile from NumPy arrays is the deck's
CSV, and the progress callback reports every position."""
import importlib.util
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import ltca

LTCA = os.environ.get("LTCA_EXE", "build/release/ltca")
ROOT = pathlib.Path(__file__).resolve().parents[2]


def run_example(name, *args):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(pathlib.Path(ltca.__file__).resolve().parents[1]))
    return subprocess.run([sys.executable, str(ROOT / "docs/examples" / name), *args], cwd=ROOT, env=env, capture_output=True, text=True)


def test_the_measured_profile_example_gives_the_deck_with_the_csv():
    # Reference: `ltca solve cases/measured_profile.toml`, whose CSV holds the same trace.
    run = run_example("measured_profile.py")
    assert run.returncode == 0, run.stderr
    cli = subprocess.run([LTCA, "solve", "cases/measured_profile.toml", "--json", "-"], cwd=ROOT, capture_output=True, text=True)
    pp = json.loads(cli.stdout)["summary"]["pp_te_arcsec"]
    assert f"measured profile  pp TE {pp:.4f} arcsec" in run.stdout


def test_a_profile_from_arrays_solves_as_the_csv_does(monkeypatch):
    monkeypatch.chdir(ROOT)
    with open("cases/data/measured_profile.csv", encoding="utf-8") as f:
        rows = [line for line in f if line.strip() and not line.lstrip().startswith("#")][1:]
    angle, deviation = np.loadtxt(rows, delimiter=",", unpack=True)
    from_file = ltca.solve("cases/measured_profile.toml")
    from_arrays = ltca.solve(ltca.Deck.load("cases/measured_profile.toml").with_measured_profile(angle, deviation))
    assert from_arrays.summary["pp_te_arcsec"] == from_file.summary["pp_te_arcsec"]
    assert np.array_equal(from_arrays.pin_force_n, from_file.pin_force_n)
    with pytest.raises(ValueError, match="abscissae"):
        ltca.Deck.load("cases/measured_profile.toml").with_measured_profile(angle, deviation[:-1])


@pytest.mark.skipif(importlib.util.find_spec("matplotlib") is None, reason="python3-matplotlib is only for the example")
def test_the_offset_sweep_example_draws_its_plot(tmp_path):
    png = tmp_path / "sweep.png"
    run = run_example("offset_sweep.py", str(png))
    assert run.returncode == 0, run.stderr
    assert png.stat().st_size > 10_000 and "23 decks" in run.stdout


def test_progress_is_called_after_every_position_and_its_exception_stops_the_sweep(monkeypatch):
    monkeypatch.chdir(ROOT)
    calls = []
    r = ltca.solve("cases/liu2021_table1.toml", progress=lambda done, total: calls.append((done, total)))
    n = len(r.crank_deg)
    assert calls == [(i, n) for i in range(1, n + 1)]

    def stop(done, total):
        if done == 3:
            raise KeyboardInterrupt("stop")
    with pytest.raises(KeyboardInterrupt):
        ltca.solve("cases/liu2021_table1.toml", progress=stop)
