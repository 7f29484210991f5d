"""ltca from Python: loaded tooth contact analysis of cycloid-pin gear pairs (docs/python.md).

A deck is read by the same reader as the command line (the same keys, the same checks: bad input
raises ValueError naming the key); an analysis runs the same library and returns the document the
command line's ``--json`` writes, as dicts (JSON null as None), with NumPy arrays beside it.

    import ltca
    deck = ltca.Deck.load("cases/liu2021_table1.toml").set("load.torque_nm", 100)
    result = ltca.solve(deck, solver="compatibility")
    result.summary["pp_te_arcsec"], result.te_arcsec, result.pin_force_n
"""
import math as _math
import os as _os

import numpy as _np

from . import _ltca

__all__ = ["Deck", "SolveResult", "Result", "solve", "geometry", "backlash", "mesh", "compare", "stiffness", "efficiency",
           "tolerance", "optimise"]


# The command line's limits and words for the options every analysis takes (docs/decks.md, Limits):
# a value beyond them is a ValueError naming the argument, a wrong type a TypeError, before any work.
_MAX_CRANK_DEG = 7200720.0       # --crank-deg (analysis::kMaxCrankDeg: two output turns of 10,001 teeth)
_MAX_THREADS = 1024              # --threads (analysis::kMaxToleranceThreads)
_MAX_SAMPLES = 10_000_000        # --samples (ToleranceSettings::kMaxSamples)
_MAX_EVALUATIONS = 1_000_000     # --evaluations (OptimiseSettings::kMaxEvaluations)
_MAX_STEPS = 10_001              # --steps (StiffnessSettings::kMaxSteps), odd
_MAX_SAMPLES_PER_FLANK = 10_000  # the profile table's points per flank (the command line writes 60)
_MAX_SEED = 2**63 - 1            # --seed
_MAX_DECK_BYTES = 4 << 20        # DeckLimits::kMaxFileBytes


def _integer(name, value, low, high, what="a whole number"):
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise TypeError(f"{name} = {value!r}: expected {what} from {low} to {high}, got {type(value).__name__}")
    value = int(value)
    if not low <= value <= high:
        raise ValueError(f"{name} = {value}: expected {what} from {low} to {high}")
    return value


def _angle(name, value):
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise TypeError(f"{name} = {value!r}: expected a number of degrees, got {type(value).__name__}")
    value = float(value)
    if not (_math.isfinite(value) and abs(value) <= _MAX_CRANK_DEG):
        raise ValueError(f"{name} = {value}: expected a finite crank angle within +-{_MAX_CRANK_DEG:g} deg")
    return value


def _flag(name, value):
    if not isinstance(value, (bool, _np.bool_)):
        raise TypeError(f"{name} = {value!r}: expected True or False, got {type(value).__name__}")
    return bool(value)


def _kinematics(value):
    if value is None:
        return ""
    if not isinstance(value, str):
        raise TypeError(f"kinematics = {value!r}: expected 'exact' or 'linearised', got {type(value).__name__}")
    if value not in ("exact", "linearised"):
        raise ValueError(f"kinematics = {value!r}: expected 'exact' or 'linearised'")
    return value


def _solver(value):
    if value is None:
        return ""
    if not isinstance(value, str):
        raise TypeError(f"solver = {value!r}: expected a solver's name, got {type(value).__name__}")
    if not value:
        raise ValueError("solver = '': expected a solver's name, or None for the deck's")
    return value


def _solvers(value):
    if isinstance(value, str) or not isinstance(value, (list, tuple)):
        raise TypeError(f"solvers = {value!r}: expected a list of solver names, got {type(value).__name__}")
    return [_solver(v) for v in value]


def _threads(value):
    return _integer("threads", value, 0, _MAX_THREADS, "0 (every hardware thread) or a thread count")


# The name the deck gives a trace handed over from Python (Deck.with_measured_profile): an in-memory
# file, read before the disk, named so in the reader's messages.
_TRACE_NAME = "<measured profile from Python>"


class Deck:
    """A deck: its TOML text, a name for messages, the folder its relative paths are read from, and
    ``--set`` overrides. Immutable: ``set`` returns a new deck. Checked when made."""

    def __init__(self, text, name="<python>", directory="", sets=()):
        self._text, self._name, self._directory, self._sets = str(text), str(name), str(directory), tuple(sets)
        self._source = _ltca.DeckSource(self._text, self._name, self._directory)  # the TOML parsed once
        self._parsed = self._source.read(list(self._sets))

    @classmethod
    def load(cls, path):
        """The deck file at path (its name as given, as the command line names it)."""
        if not isinstance(path, (str, _os.PathLike)):
            raise TypeError(f"path = {path!r}: expected the path of a deck file, got {type(path).__name__}")
        path = _os.fspath(path)
        if not _os.path.isfile(path):
            raise ValueError(f"deck '{path}': no such file; expected a deck file (TOML)")
        size = _os.path.getsize(path)  # before reading: a deck is small
        if size > _MAX_DECK_BYTES:
            raise ValueError(f"deck '{path}': the file is {size} bytes; expected a deck of at most {_MAX_DECK_BYTES} bytes "
                             f"({_MAX_DECK_BYTES >> 20} MiB; docs/decks.md, Limits)")
        with open(path, encoding="utf-8", errors="surrogateescape") as f:
            text = f.read(_MAX_DECK_BYTES + 1)
        return cls(text, path, _os.path.dirname(path) or ".")

    @classmethod
    def from_toml(cls, text, name="<python>", directory=""):
        return cls(text, name, directory)

    @classmethod
    def from_dict(cls, sections, name="<python>", directory=""):
        """A deck from {"section": {"key": value, ...}, ...}: the keys of a deck file."""
        if not isinstance(sections, dict):
            raise ValueError(f"deck {name}: expected a dict of sections, got {type(sections).__name__}")
        return cls(_ltca._toml_deck(sections), name, directory)  # the deck writer of ltca (C++)

    def set(self, key, value):
        """A new deck with "section.key" set to value, as ``ltca --set section.key=value``."""
        return self.update({key: value})

    def unset(self, *paths):
        """A new deck without each "section" or "section.key", as ``ltca --unset`` (one reading of
        the deck for all of them, so that sections that belong together go together:
        ``unset("output", "bearing")``); the deck must have each (ValueError otherwise)."""
        for path in paths:
            if not isinstance(path, str) or not path or path.startswith("-") or "=" in path:
                raise ValueError(f"unset {path!r}: expected section or section.key, e.g. 'friction' or 'load.torque_nm'")
        return self._derived(self._source, tuple("-" + path for path in paths))

    def update(self, values):
        """A new deck with every "section.key" of the dict set to its value (one reading of the
        deck for all of them)."""
        sets = tuple(_ltca._toml_set(str(k), v) for k, v in values.items())  # the deck writer of ltca (C++)
        return self._derived(self._source, sets)

    def _derived(self, source, sets):
        """This deck read from source (its parsed text, with in-memory files) with more overrides."""
        deck = Deck.__new__(Deck)
        deck._text, deck._name, deck._directory, deck._sets = self._text, self._name, self._directory, self._sets + sets
        deck._source = source
        deck._parsed = source.read(list(deck._sets))
        return deck

    def with_measured_profile(self, abscissa, deviation_um, abscissa_name="profile_angle_deg"):
        """A new deck whose [errors] profile_measured_csv is this trace, from NumPy arrays (or
        lists): the abscissa in deg (abscissa_name "profile_angle_deg") or mm ("arc_length_mm"),
        the normal deviation in um (+ adds material), as a measuring centre's CSV gives them
        (docs/decks.md). The trace stays in memory, no file is written: the deck names it
        "<measured profile from Python>" (profile_measured_csv, and the reader's messages) and reads
        it by the same reader as a deck's CSV, with the same checks."""
        if abscissa_name not in ("profile_angle_deg", "arc_length_mm"):
            raise ValueError(f"abscissa_name = {abscissa_name!r}: expected 'profile_angle_deg' or 'arc_length_mm'")
        x = _np.asarray(abscissa, dtype=float).ravel()
        y = _np.asarray(deviation_um, dtype=float).ravel()
        if x.shape != y.shape:
            raise ValueError(f"profile trace: {x.size} abscissae for {y.size} deviations; expected as many of each")
        source = _ltca._with_profile_trace(self._source, _TRACE_NAME, abscissa_name, x, y)
        return self._derived(source, (_ltca._toml_set("errors.profile_measured_csv", _TRACE_NAME),))

    @property
    def name(self):
        return self._name

    @property
    def text(self):
        return self._text

    @property
    def sets(self):
        return self._sets

    def __repr__(self):
        return f"ltca.Deck({self._name!r}, {len(self._sets)} override(s))"


class SolveResult:
    """``ltca solve``: ``json`` is the document of ``ltca solve --json`` (dicts, None for null);
    ``summary`` its summary; the arrays (NumPy, a row per crank position, NaN where the position
    failed): crank_deg, te_arcsec, contacts, pin_force_n and contact_stress_mpa (positions x pins;
    two discs: disc 1's pins, then disc 2's), disc_torque_nm (two discs), and position_status (a list)."""

    def __init__(self, document, summary, arrays, spectrum_succeeded=True):
        self._document, self._json = document, None
        self.summary = summary
        self.status = self.summary["status"]
        # With [[load_spectrum]]: every bin's every position succeeded too (ltca solve's exit 0).
        self.spectrum_succeeded = spectrum_succeeded
        for key, value in arrays.items():
            setattr(self, key, value)

    @property
    def json(self):
        """The whole document (converted on first use: its per-position records are many)."""
        if self._json is None:
            self._json = self._document.to_python()
        return self._json

    @property
    def succeeded(self):
        return self.status == "success" and self.spectrum_succeeded

    def __repr__(self):
        return f"ltca.SolveResult(status {self.status!r}, {len(self.crank_deg)} positions)"


def _deck(deck):
    if isinstance(deck, Deck):
        return deck
    if isinstance(deck, (str, _os.PathLike)):
        return Deck.load(deck)
    raise TypeError(f"deck = {deck!r}: expected an ltca.Deck or the path of a deck file, got {type(deck).__name__}")


def solve(deck, solver=None, kinematics=None, progress=None):
    """The loaded sweep of the deck (``ltca solve``); solver and kinematics as --solver and
    --kinematics (None: the deck's); progress: None or a callable progress(done, total) called
    after each crank position (an exception it raises stops the sweep and propagates). Units as
    the keys say: deg, arcsec, N, MPa, N*m."""
    d = _deck(deck)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress = {progress!r}: expected None or a callable progress(done, total)")
    document, summary, arrays, spectrum_succeeded = _ltca.solve(d._parsed, _solver(solver), _kinematics(kinematics), progress)
    return SolveResult(document, summary, arrays, spectrum_succeeded)


class Result:
    """An analysis: ``json`` is the document its command writes with ``--json`` (dicts, None for
    null), produced in this process by the command's own writer; ``summary`` its summary (or None);
    ``exit_code`` the command's (0: everything succeeded, 1: some part did not); ``tables`` every
    list of records at the top of the document (positions, pins, solvers, history) as {column:
    NumPy array}, built from the result in C++ (a column per numeric key, NaN for null); and
    ``csv`` the per-row table of the command's ``--csv`` where it carries one (tolerance: a row per
    sample; geometry: the profile; optimise: a row per evaluation), as {column: NumPy array}."""

    def __init__(self, command, code, doc, columns=None, tables=None):
        self.command = command
        self.exit_code = code
        self.json = doc
        self.summary = doc.get("summary") if isinstance(doc, dict) else None
        tables = dict(tables or {})  # built from the result (no document read): by key at the top, by path further in
        self.tables = {k: v for k, v in tables.items() if isinstance(k, str)}
        self._nested = {k: v for k, v in tables.items() if isinstance(k, tuple)}
        if isinstance(columns, str):
            raise TypeError("columns: expected a dict of {column: array} built from the result (CSV text is no longer read)")
        self.csv = dict(columns or {})  # the per-row table, built from the result as columns (no CSV parsed)

    @property
    def succeeded(self):
        return self.exit_code == 0

    def table(self, *path):
        """The list of records at path in the document as {column: NumPy array}, e.g. the stiffness
        loop's curve at the first crank: ``result.table("positions", 0, "curve")``; built from the
        result, as ``tables`` (the document is only walked to check the path)."""
        if len(path) == 1 and path[0] in self.tables:
            return self.tables[path[0]]
        # An index as the document's lists take it: a negative one counts from the end.
        node, steps = self.json, []
        for step in path:
            if isinstance(node, list) and isinstance(step, int) and not isinstance(step, bool) and -len(node) <= step < 0:
                step += len(node)
            steps.append(step)
            node = node[step] if isinstance(node, (list, dict)) else node
        path = tuple(steps)
        if path in self._nested:
            return self._nested[path]
        node = self.json
        for step in path:
            node = node[step]
        if not (isinstance(node, list) and all(isinstance(r, dict) for r in node)):
            raise ValueError(f"{path}: expected a list of records in the document")
        if node:
            raise LookupError(f"{path}: a list of records that no result of ltca builds as a table")
        return {}

    def __repr__(self):
        return f"ltca.Result({self.command!r}, exit code {self.exit_code}, tables {sorted(self.tables)})"


def _run(name, deck, *args):
    d = _deck(deck)
    code, doc, columns, tables = getattr(_ltca, name)(d._parsed, *args)
    return Result(name, code, doc, columns, tables)


def geometry(deck, crank_deg=0.0, samples_per_flank=60):
    """``ltca geometry``: the derived geometry; ``csv`` the profile (mm) at crank_deg (deg)."""
    return _run("geometry", deck, _angle("crank_deg", crank_deg),
                _integer("samples_per_flank", samples_per_flank, 2, _MAX_SAMPLES_PER_FLANK))


def backlash(deck, kinematics=None):
    """``ltca backlash``: unloaded TCA over the sweep (arcsec); ``tables["positions"]``."""
    return _run("backlash", deck, _kinematics(kinematics))


def mesh(deck, crank_deg=0.0):
    """``ltca mesh``: the mesh state of every pin at crank_deg (deg); ``tables["pins"]``."""
    return _run("mesh", deck, _angle("crank_deg", crank_deg))


def compare(deck, solvers=(), kinematics=None):
    """``ltca compare``: several solvers on the same sweep (all registered ones by default)."""
    return _run("compare", deck, _solvers(solvers), _kinematics(kinematics))


def stiffness(deck, solver=None, kinematics=None, crank_deg=None, steps=None):
    """``ltca stiffness``: the torque-twist loop (N*m, arcmin); options as --crank-deg, --steps."""
    if steps is not None:
        steps = _integer("steps", steps, 3, _MAX_STEPS, "an odd number of torque levels")
        if steps % 2 == 0:
            raise ValueError(f"steps = {steps}: expected an odd number of torque levels from 3 to {_MAX_STEPS}")
    return _run("stiffness", deck, _solver(solver), _kinematics(kinematics), None if crank_deg is None else _angle("crank_deg", crank_deg),
                steps)


def efficiency(deck, solver=None, kinematics=None):
    """``ltca efficiency``: friction, power loss (W) and efficiency over the sweep."""
    return _run("efficiency", deck, _solver(solver), _kinematics(kinematics))


def tolerance(deck, samples=None, seed=None, threads=0, lost_motion=False, no_worst_case=False, solver=None, kinematics=None):
    """``ltca tolerance``: the Monte Carlo of [tolerances]; ``csv`` a row per sample (its inputs
    and figures), as --csv writes it. threads 0: every hardware thread."""
    return _run("tolerance", deck, _solver(solver), _kinematics(kinematics),
                None if samples is None else _integer("samples", samples, 1, _MAX_SAMPLES),
                None if seed is None else _integer("seed", seed, 0, _MAX_SEED), _threads(threads),
                _flag("lost_motion", lost_motion), _flag("no_worst_case", no_worst_case))


def optimise(deck, threads=0, evaluations=None, solver=None, kinematics=None):
    """``ltca optimise``: the search of [optimise]; ``csv`` a row per evaluation."""
    return _run("optimise", deck, _solver(solver), _kinematics(kinematics), _threads(threads),
                None if evaluations is None else _integer("evaluations", evaluations, 1, _MAX_EVALUATIONS))


# The generic analyses of the table of analyses (solvers/app/documents/analyses.hpp): a function
# each, made from the compiled module's list, so that a new analysis needs no line here. Keyword
# arguments are the entry's options ('_' for the command line's '-'; None: the default), checked by
# the same rule as the command line's; the answer is a Result like the other analyses'.
def _analysis_function(entry):
    import inspect as _inspect
    name = entry["name"]

    def run(deck, **options):
        d = _deck(deck)
        code, doc, columns, tables = getattr(_ltca, name)(d._parsed, **options)
        return Result(name, code, doc, columns, tables)

    run.__name__ = run.__qualname__ = name
    run.__doc__ = getattr(_ltca, name).__doc__
    parameters = [_inspect.Parameter("deck", _inspect.Parameter.POSITIONAL_OR_KEYWORD)]
    parameters += [_inspect.Parameter(o["name"], _inspect.Parameter.KEYWORD_ONLY, default=None) for o in entry["options"]]
    run.__signature__ = _inspect.Signature(parameters)
    return run


for _entry in _ltca._analyses():
    if _entry["generic"]:
        globals()[_entry["name"]] = _analysis_function(_entry)
        __all__.append(_entry["name"])
del _entry
