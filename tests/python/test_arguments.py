"""Issue 46: the module takes what the command line takes. Every argument is checked with the
command line's limits before any work: a value beyond them is a ValueError naming the argument, a
wrong type a TypeError naming it. Before, samples_per_flank=10**6 took 24 GB before the kernel
killed the process, crank_deg=nan and negative counts ran or raised TypeError/AttributeError
without the argument's name, and Deck.load read a whole file before the 4 MiB check."""
import math
import pathlib

import numpy as np
import pytest

import ltca

ROOT = pathlib.Path(__file__).resolve().parents[2]
TABLE1 = str(ROOT / "cases" / "liu2021_table1.toml")
TOLERANCES = str(ROOT / "cases" / "jiang2022_tolerances.toml")
OPTIMISE = str(ROOT / "cases" / "liu2021_optimise.toml")

BAD_VALUES = [
    (ltca.geometry, TABLE1, {"samples_per_flank": 10**6}, "samples_per_flank"),
    (ltca.geometry, TABLE1, {"samples_per_flank": 1}, "samples_per_flank"),
    (ltca.geometry, TABLE1, {"crank_deg": math.nan}, "crank_deg"),
    (ltca.geometry, TABLE1, {"crank_deg": math.inf}, "crank_deg"),
    (ltca.geometry, TABLE1, {"crank_deg": 1e7}, "crank_deg"),
    (ltca.mesh, TABLE1, {"crank_deg": -math.inf}, "crank_deg"),
    (ltca.backlash, TABLE1, {"kinematics": "exactly"}, "kinematics"),
    (ltca.solve, TABLE1, {"kinematics": "fast"}, "kinematics"),
    (ltca.solve, TABLE1, {"solver": ""}, "solver"),
    (ltca.solve, TABLE1, {"solver": "no-such-solver"}, "no-such-solver"),
    (ltca.compare, TABLE1, {"solvers": ["bisection", ""]}, "solver"),
    (ltca.stiffness, TABLE1, {"steps": 4}, "steps"),
    (ltca.stiffness, TABLE1, {"steps": -5}, "steps"),
    (ltca.stiffness, TABLE1, {"steps": 10**9}, "steps"),
    (ltca.stiffness, TABLE1, {"crank_deg": math.nan}, "crank_deg"),
    (ltca.efficiency, TABLE1, {"kinematics": "both"}, "kinematics"),
    (ltca.tolerance, TOLERANCES, {"samples": 0}, "samples"),
    (ltca.tolerance, TOLERANCES, {"samples": -3}, "samples"),
    (ltca.tolerance, TOLERANCES, {"samples": 10**8}, "samples"),
    (ltca.tolerance, TOLERANCES, {"seed": -1}, "seed"),
    (ltca.tolerance, TOLERANCES, {"threads": -1}, "threads"),
    (ltca.tolerance, TOLERANCES, {"threads": 5000}, "threads"),
    (ltca.optimise, OPTIMISE, {"threads": 2000}, "threads"),
    (ltca.optimise, OPTIMISE, {"evaluations": 0}, "evaluations"),
    (ltca.optimise, OPTIMISE, {"evaluations": 10**7}, "evaluations"),
]

BAD_TYPES = [
    (ltca.geometry, TABLE1, {"samples_per_flank": 60.5}, "samples_per_flank"),
    (ltca.geometry, TABLE1, {"samples_per_flank": "60"}, "samples_per_flank"),
    (ltca.geometry, TABLE1, {"crank_deg": "3"}, "crank_deg"),
    (ltca.mesh, TABLE1, {"crank_deg": None}, "crank_deg"),
    (ltca.solve, TABLE1, {"kinematics": 1}, "kinematics"),
    (ltca.solve, TABLE1, {"solver": 3}, "solver"),
    (ltca.solve, TABLE1, {"progress": 5}, "progress"),
    (ltca.compare, TABLE1, {"solvers": "bisection"}, "solvers"),
    (ltca.stiffness, TABLE1, {"steps": 5.0}, "steps"),
    (ltca.tolerance, TOLERANCES, {"samples": 2.5}, "samples"),
    (ltca.tolerance, TOLERANCES, {"samples": True}, "samples"),
    (ltca.tolerance, TOLERANCES, {"lost_motion": "yes"}, "lost_motion"),
    (ltca.tolerance, TOLERANCES, {"no_worst_case": 1}, "no_worst_case"),
    (ltca.optimise, OPTIMISE, {"threads": "4"}, "threads"),
]


@pytest.mark.parametrize("function, deck, kwargs, name", BAD_VALUES,
                         ids=[f"{f.__name__}-{next(iter(k))}={next(iter(k.values()))!r}" for f, _, k, _ in BAD_VALUES])
def test_a_value_beyond_the_command_lines_limits_is_a_value_error_naming_it(function, deck, kwargs, name):
    with pytest.raises(ValueError, match=name):
        function(deck, **kwargs)


@pytest.mark.parametrize("function, deck, kwargs, name", BAD_TYPES,
                         ids=[f"{f.__name__}-{next(iter(k))}={next(iter(k.values()))!r}" for f, _, k, _ in BAD_TYPES])
def test_a_wrong_type_is_a_type_error_naming_it(function, deck, kwargs, name):
    with pytest.raises(TypeError, match=name):
        function(deck, **kwargs)


def test_the_numpy_scalars_a_sweep_makes_are_taken():
    assert ltca.geometry(TABLE1, crank_deg=np.float64(3.0), samples_per_flank=np.int64(20)).succeeded


def test_a_deck_that_is_not_a_deck_is_a_type_error():
    with pytest.raises(TypeError, match="deck"):
        ltca.backlash(42)
    with pytest.raises(TypeError, match="path"):
        ltca.Deck.load(3.5)


def test_a_deck_file_over_the_limit_is_refused_before_it_is_read(tmp_path):
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:
        f.truncate((4 << 20) + 1)  # sparse: nothing is written, nothing must be read
    with pytest.raises(ValueError, match="at most 4194304 bytes"):
        ltca.Deck.load(big)
