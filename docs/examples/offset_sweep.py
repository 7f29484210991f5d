"""A parameter sweep in Python (docs/python.md): peak-to-peak loaded TE and mean backlash of the
Liu 2021 Table 1 pair against the offset modification dR_p, one deck per value, plotted with
Matplotlib.

    PYTHONPATH=build/release/python /usr/bin/python3 docs/examples/offset_sweep.py offset_sweep.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import ltca

base = ltca.Deck.load("cases/liu2021_optimise.toml").set("modification.pin_radius_mm", -0.004)
offsets_um = np.linspace(-30.0, -8.0, 23)  # dR_p; with dR_rp = -4 um the pins interfere above about -6
pp_te, backlash = [], []
for dp in offsets_um:
    deck = base.set("modification.pin_circle_radius_mm", dp / 1000.0)
    solved = ltca.solve(deck, solver="compatibility")
    pp_te.append(solved.summary["pp_te_arcsec"] if solved.succeeded else np.nan)
    backlash.append(ltca.backlash(deck).summary["mean_backlash_arcsec"])

fig, ax = plt.subplots(figsize=(8, 4.5))
ax.plot(offsets_um, pp_te, "o-", color="tab:blue", label="peak-to-peak loaded TE")
ax.set_xlabel("offset modification dR_p (um), dR_rp = -4 um")
ax.set_ylabel("peak-to-peak loaded TE (arcsec)", color="tab:blue")
twin = ax.twinx()
twin.plot(offsets_um, backlash, "s--", color="tab:orange", label="mean backlash")
twin.set_ylabel("mean backlash (arcsec)", color="tab:orange")
ax.set_title("Liu 2021 Table 1 pair, T = 206 N*m: a sweep of 23 decks built in Python")
ax.grid(True, alpha=0.3)
lines = ax.get_lines() + twin.get_lines()
ax.legend(lines, [l.get_label() for l in lines], loc="lower left")  # the corner both curves leave empty
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "offset_sweep.png", dpi=100)
print(f"{len(offsets_um)} decks; pp TE {np.nanmin(pp_te):.4f} .. {np.nanmax(pp_te):.4f} arcsec; "
      f"backlash {min(backlash):.2f} .. {max(backlash):.2f} arcsec")
