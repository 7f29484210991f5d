"""A measured profile from NumPy arrays (docs/python.md): the trace of a measuring centre as two
arrays (profile angle in deg, normal deviation in um) given to a deck built in Python; the loaded
TE with and without it.

    PYTHONPATH=build/release/python /usr/bin/python3 docs/examples/measured_profile.py
"""
import tomllib

import numpy as np

import ltca

# The deck of cases/measured_profile.toml as a dict, without its trace file.
with open("cases/measured_profile.toml", "rb") as f:
    sections = tomllib.load(f)
del sections["errors"]["profile_measured_csv"]
base = ltca.Deck.from_dict(sections, name="measured_profile (from Python)")

# The arrays: here read from the example trace; in a study they come from the measurement.
with open("cases/data/measured_profile.csv", encoding="utf-8") as f:
    rows = [line for line in f if line.strip() and not line.lstrip().startswith("#")][1:]  # comments, then the header
angle_deg, deviation_um = np.loadtxt(rows, delimiter=",", unpack=True)
measured = base.with_measured_profile(angle_deg, deviation_um)

for name, deck in (("nominal profile", base), ("measured profile", measured)):
    r = ltca.solve(deck)
    print(f"{name:17s} pp TE {r.summary['pp_te_arcsec']:.4f} arcsec, mean TE {r.summary['mean_te_arcsec']:.4f} arcsec, "
          f"largest stress {np.nanmax(r.contact_stress_mpa):.1f} MPa")
