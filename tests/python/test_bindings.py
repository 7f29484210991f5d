"""The module's table of bindings (solvers/app/python/module.cpp, kBindings) against the package and
the command line: every analysis the compiled module binds is a function of the package, every
analysis of the package has its binding, and each is a command of the command line's table (its
docstring names it, and `ltca NAME --help` gives its own usage line)."""
import inspect
import os
import pathlib
import subprocess

import pytest

import ltca
from ltca import _ltca

LTCA = os.environ.get("LTCA_EXE", "build/release/ltca")
ROOT = pathlib.Path(__file__).resolve().parents[2]

BINDINGS = sorted(n for n, f in vars(_ltca).items() if callable(f) and not inspect.isclass(f) and not n.startswith("_"))
ANALYSES = sorted(n for n in ltca.__all__ if inspect.isfunction(getattr(ltca, n)))


def test_every_binding_is_an_analysis_of_the_package_and_back():
    assert BINDINGS == ANALYSES
    assert len(BINDINGS) >= 9  # solve, geometry, backlash, mesh, compare, stiffness, efficiency, tolerance, optimise


@pytest.mark.parametrize("name", BINDINGS)
def test_a_binding_is_a_command_of_the_command_line(name):
    assert f"ltca {name}:" in getattr(_ltca, name).__doc__
    run = subprocess.run([LTCA, name, "--help"], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert f"Usage: ltca {name} " in run.stdout  # not the top-level help that an unknown name gets


TABLE = _ltca._analyses()  # the table of analyses (solvers/app/documents/analyses.hpp)


def test_every_analysis_of_the_table_is_a_binding_and_a_function_of_the_package_and_back():
    names = sorted(e["name"] for e in TABLE)
    assert len(names) == len(set(names))
    assert names == BINDINGS
    assert names == ANALYSES


GENERIC = [e for e in TABLE if e["generic"]]


@pytest.mark.parametrize("entry", GENERIC, ids=[e["name"] for e in GENERIC])
def test_a_generic_analysis_takes_its_entrys_options_as_keywords(entry):
    function = getattr(ltca, entry["name"])
    assert list(inspect.signature(function).parameters)[1:] == [o["name"] for o in entry["options"]]
    result = function(ROOT / "cases" / "liu2021_table1.toml")
    assert result.exit_code == 0 and isinstance(result.json, dict) and result.json
    with pytest.raises(TypeError):
        function(ROOT / "cases" / "liu2021_table1.toml", no_such_option=1)
