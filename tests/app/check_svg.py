#!/usr/bin/env python3
"""Issue 16: every plot type is written for every deck in cases/ and is a well-formed SVG whose
axis labels, series and marks are there to read.

    check_svg.py LTCA CASES_DIR OUT_DIR [PLOT ...]
    check_svg.py --file SVG PANELS SERIES_PER_PANEL   (one figure: its panels and labelled series)

PLOT is one of geometry, solve, stiffness, tolerance, efficiency, backlash, mesh, compare
(default: all). A plot whose
command does not apply to a deck (solve without [material], tolerance without [tolerances],
efficiency without [friction]) is listed as not applicable (both take two discs since issue 27). Each SVG is parsed with a real XML parser
(xml.etree.ElementTree). Checked per figure:
  - the root is <svg> with a <title> and a <desc> (the caption naming the deck);
  - the <metadata> lists the panels; every panel's axis labels are drawn as <text>;
  - the number of labelled series is what the plot type must show, and with more than one series
    each label is drawn (the legend);
  - the title names the crank angle or range, and the plot-type marks (mean and peak-to-peak of the
    TE, pin numbers, the exaggeration factor of the clearances) are drawn.
"""
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"
LTCA = "{urn:ltca:plots}"


def texts(root):
    """Every drawn text, its <tspan> pieces joined."""
    return ["".join(t.itertext()) for t in root.iter(SVG + "text")]


def parse(path):
    root = ET.parse(path).getroot()  # raises on a malformed document
    if root.tag != SVG + "svg":
        raise AssertionError(f"{path}: root is {root.tag}, not svg")
    title = root.find(SVG + "title")
    desc = root.find(SVG + "desc")
    if title is None or not title.text or desc is None or not desc.text:
        raise AssertionError(f"{path}: no <title> or <desc>")
    figure = root.find(f"{SVG}metadata/{LTCA}figure")
    if figure is None:
        raise AssertionError(f"{path}: no ltca:figure metadata")
    drawn = texts(root)
    panels = []
    for panel in figure.findall(LTCA + "panel"):
        labels = [s.get("label") for s in panel.findall(LTCA + "series")]
        if int(panel.get("series")) != len(labels):
            raise AssertionError(f"{path}: panel '{panel.get('title')}' says {panel.get('series')} series, lists {len(labels)}")
        for axis in ("x_label", "y_label"):
            if not panel.get(axis) or panel.get(axis) not in drawn:
                raise AssertionError(f"{path}: the {axis} '{panel.get(axis)}' is not drawn")
        if len(labels) > 1:
            for label in labels:
                if label not in drawn:
                    raise AssertionError(f"{path}: the legend does not show '{label}'")
        panels.append({"title": panel.get("title"), "x": panel.get("x_label"), "y": panel.get("y_label"),
                       "z": panel.get("z_label"), "cells": panel.get("cells"), "series": labels})
    return title.text, desc.text, panels, drawn


def expect(cond, message):
    if not cond:
        raise AssertionError(message)


def check_geometry(path, deck):
    title, caption, panels, drawn = parse(path)
    expect("crank 3 deg" in title, f"{path}: the title does not name the crank angle: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    expect(len(panels) == 1, f"{path}: {len(panels)} panels, expected 1")
    p = panels[0]
    expect((p["x"], p["y"]) == ("x_f (mm)", "y_f (mm)"), f"{path}: axes {p['x']}, {p['y']}")
    # cycloid, pin circle, [pins], first contact, line of centres, cycloid centre; a stage (issue 25,
    # [output]) adds its holes and output pins (2) or its crank circle and both centres (3)
    stage = [s for s in p["series"] if s.startswith(("holes r_h", "output pins r_w", "crank circle", "crankshaft centres",
                                                     "crank-hole centres"))]
    text = open(deck).read()
    expected_stage = 0 if "[output]" not in text else (2 if 'kind = "pins"' in text else 3)
    expect(len(stage) == expected_stage, f"{path}: stage series {stage}, expected {expected_stage}")
    base = len(p["series"]) - len(stage)
    expect(base in (5, 6), f"{path}: {base} series besides the stage's, expected 5 or 6: {p['series']}")
    for label in ("line of centres O_p O_c", "first contact (least clearance)"):
        expect(label in p["series"], f"{path}: no series '{label}'")
    expect(re.match(r"clearances drawn x\d", p["title"] or ""), f"{path}: no exaggeration factor in '{p['title']}'")
    z_p = int(re.search(r"z_p = (\d+)", caption).group(1))
    missing = [j for j in range(1, z_p + 1) if str(j) not in drawn]
    expect(not missing, f"{path}: pin numbers not drawn: {missing}")


def check_solve(path, deck, discs):
    title, caption, panels, drawn = parse(path)
    expect(re.search(r"crank [-\d.e+]+ to [-\d.e+]+ deg", title), f"{path}: the title does not name the crank range: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    if "no position succeeded" in title:
        expect(len(panels) == 1, f"{path}: {len(panels)} panels without a successful position")
    else:
        # The slice model (issue 11) adds the contact pattern across the face width.
        sliced = re.search(r"model slices", caption) is not None
        # Both discs bear on one pin ring, numbered 1 .. z_p: a force map and a stress map per disc.
        maps_expected = 2 * discs
        expected = 3 + maps_expected + (1 if sliced else 0)
        expect(len(panels) == expected, f"{path}: {len(panels)} panels, expected {expected}")
        if sliced:
            p = panels[-1]
            expect((p["x"], p["y"], p["z"]) == ("face width position z (mm)", "pin number", "slice force (N)"),
                   f"{path}: contact pattern axes {p['x']}, {p['y']}, {p['z']}")
            expect(p["z"] in drawn, f"{path}: the contact pattern's colour bar label is not drawn")
            panels = panels[:-1]
        axes = [(p["x"], p["y"]) for p in panels]
        # Two discs (issue 27): the second disc's maps say that its crank is the axis + 180 deg.
        map_axes = [("crank angle (deg)", "pin number")] * maps_expected
        if discs == 2:
            map_axes = [("crank angle (deg)", "pin number"), ("crank angle (deg); disc 2 at +180 deg", "pin number")] * 2
        expect(axes == [("crank angle (deg)", "TE (arcsec)"), ("pin number", "pin force (N)"),
                        ("pin number", "contact stress (MPa)")] + map_axes,
               f"{path}: axes {axes}")
        # The pin x crank maps: their colour bars labelled with the unit, a cell per pin and kept position.
        maps = [(p["z"], p["cells"]) for p in panels[3:]]
        expect([z for z, _ in maps] == ["pin force (N)"] * discs + ["contact stress (MPa)"] * discs, f"{path}: map labels {maps}")
        for z, _ in maps:
            expect(z in drawn, f"{path}: the colour bar label '{z}' is not drawn")
        crank = r"cranks [-\d.e+]+ / [-\d.e+]+ deg" if discs == 2 else r"crank [-\d.e+]+ deg"  # both discs' cranks
        expect(re.search(crank, panels[1]["title"]), f"{path}: the force bars do not name the crank angle(s): {panels[1]['title']}")
        bars = 2 if discs == 2 else 0  # one disc: one unlabelled series (no legend); two: disc 1, disc 2
        expect(len(panels[1]["series"]) == bars and len(panels[2]["series"]) == bars,
               f"{path}: bar series {panels[1]['series']}, expected {bars} labelled")
    p = panels[0]
    expect(len(p["series"]) == 1, f"{path}: TE series {p['series']}, expected 1")
    if "no position succeeded" not in title:
        expect(any(t.startswith("mean ") and t.endswith(" arcsec") for t in drawn), f"{path}: the mean TE is not marked")
        expect(any("peak-to-peak" in t for t in drawn), f"{path}: the peak-to-peak TE is not marked")


def check_stiffness(path, deck, code):
    title, caption, panels, drawn = parse(path)
    expect("crank 0 deg" in title, f"{path}: the title does not name the crank angle: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    expect(len(panels) == 1, f"{path}: {len(panels)} panels, expected 1")
    p = panels[0]
    expect(p["x"].startswith("twist (arcmin") and p["y"] == "torque (N*m)", f"{path}: axes {p['x']}, {p['y']}")
    if "no solve succeeded" in title:
        return
    expect(p["series"] and p["series"][0] == "torque-twist loop", f"{path}: no loop series: {p['series']}")
    # With every solve a success (exit 0) the read-offs are all there; a failed solve (exit 1,
    # cases/hard/law_cannot_carry.toml) leaves out the ones it would have given.
    for word in ("rigidity", "lost motion") if code == 0 else ():
        expect(any(word in label for label in p["series"]), f"{path}: '{word}' is not in the legend {p['series']}")


def check_tolerance(path, deck, code):
    title, caption, panels, drawn = parse(path)
    expect(re.search(r"crank [-\d.e+]+ to [-\d.e+]+ deg", title), f"{path}: the title does not name the crank range: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    # A reducer stage ([output], issue 28) adds its largest output-pin force (output pins), bearing
    # load and shortest bearing life (when the deck rates its bearings).
    with open(deck, encoding="utf-8") as f:
        stage = any(line.strip().startswith("[output]") for line in f)
    allowed = range(8, 13) if stage else (8, 9)
    expect(len(panels) in allowed, f"{path}: {len(panels)} histograms, expected 8 (9 with lost motion; up to 3 more on a stage)")
    for p in panels:
        expect(p["y"] == "samples per bin" and p["x"].endswith(")"), f"{path}: axes {p['x']}, {p['y']}")
        expect(p["series"] == ["samples"], f"{path}: series {p['series']}")
    # 6 samples (the tolerance run below: --samples 6): the median is marked on every histogram, p5 and p95 on none
    # (a percentile only where n min(p, 1 - p) >= 1: p5 and p95 need 20 samples; docs/tolerance.md).
    expect(drawn.count("p50") == len(panels), f"{path}: 'p50' is not marked on every histogram")
    for mark in ("p5", "p95"):
        expect(drawn.count(mark) == 0, f"{path}: '{mark}' is marked from 6 samples")


def check_efficiency(path, deck, code):
    title, caption, panels, drawn = parse(path)
    expect(re.search(r"crank [-\d.e+]+ to [-\d.e+]+ deg", title), f"{path}: the title does not name the crank range: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    axes = [(p["x"], p["y"]) for p in panels]
    expect(axes == [("crank angle (deg)", "efficiency (-)"), ("crank angle (deg)", "power loss (W)"),
                    ("crank angle (deg)", "friction coefficient (-)")], f"{path}: axes {axes}")
    expect(panels[0]["series"] == ["efficiency", "first order"], f"{path}: series {panels[0]['series']}")


def check_backlash(path, deck, code):
    title, caption, panels, drawn = parse(path)
    expect(re.search(r"crank [-\d.e+]+ to [-\d.e+]+ deg", title), f"{path}: the title does not name the crank range: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    axes = [(p["x"], p["y"]) for p in panels]
    expect(axes == [("crank angle (deg)", "backlash (arcsec)"), ("crank angle (deg)", "rotation to first contact (arcsec)")],
           f"{path}: axes {axes}")
    expect([len(p["series"]) for p in panels] == [1, 2], f"{path}: series {[p['series'] for p in panels]}")
    expect(any(t.startswith("mean ") for t in drawn) and any("peak-to-peak" in t for t in drawn),
           f"{path}: the mean and peak-to-peak backlash are not marked")


def check_mesh(path, deck, code):
    title, caption, panels, drawn = parse(path)
    expect("crank 3 deg" in title, f"{path}: the title does not name the crank angle: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    axes = [(p["x"], p["y"]) for p in panels]
    expect(axes == [("pin number", "clearance (um)"), ("pin number", "arm L_i (mm)")], f"{path}: axes {axes}")
    expect(re.match(r"least clearance .* at pin \d+", panels[0]["title"] or ""), f"{path}: the least clearance is not named")


def check_compare(path, deck, code):
    title, caption, panels, drawn = parse(path)
    expect(re.search(r"crank [-\d.e+]+ to [-\d.e+]+ deg", title), f"{path}: the title does not name the crank range: {title}")
    expect(deck in caption, f"{path}: the caption does not name the deck")
    expect(len(panels) == 2, f"{path}: {len(panels)} panels, expected 2")
    expect(panels[0]["series"] == ["bisection", "compatibility"] and panels[1]["series"] == ["compatibility"],
           f"{path}: series {[p['series'] for p in panels]}")
    # The differences in a unit of their size (issue 27): "(arcsec)" or "(1e-9 arcsec)" and the like.
    expect(re.fullmatch(r"TE - TE of bisection \((1e-\d+ )?arcsec\)", panels[1]["y"] or ""),
           f"{path}: difference axis {panels[1]['y']}")


# plot: (command line after the deck, exit codes that still owe the figure, the section it needs)
COMMANDS = {
    "stiffness": (["--crank-deg", "0", "--steps", "9"], (0, 1), "[material]"),
    "tolerance": (["--samples", "6", "--threads", "1", "--set", "sweep.positions=3"], (0, 1), "[tolerances]"),
    "efficiency": (["--set", "sweep.positions=3"], (0, 1), "[friction]"),
    "backlash": (["--set", "sweep.positions=5"], (0,), "[pair]"),
    "mesh": (["--crank-deg", "3"], (0,), "[pair]"),
    "compare": (["--solvers", "bisection,compatibility", "--set", "sweep.positions=3"], (0, 1), "[material]"),
}
CHECKS = {"stiffness": check_stiffness, "tolerance": check_tolerance, "efficiency": check_efficiency,
          "backlash": check_backlash, "mesh": check_mesh, "compare": check_compare}


def decks(cases_dir):
    out = []
    for folder, _, files in os.walk(cases_dir):
        out += [os.path.join(folder, f) for f in files if f.endswith(".toml")]
    return sorted(out)


def check_file(path, panels, series):
    """One figure written by a test: parsed, its panel count and each panel's labelled series."""
    try:
        _, _, found, _ = parse(path)
        expect(len(found) == panels, f"{path}: {len(found)} panels, expected {panels}")
        for p in found:
            expect(len(p["series"]) == series, f"{path}: panel '{p['title']}' has series {p['series']}, expected {series}")
    except (AssertionError, ET.ParseError, OSError) as e:
        print("FAIL", e)
        return 1
    return 0


def main():
    if sys.argv[1] == "--file":
        return check_file(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    ltca, cases_dir, out_dir = sys.argv[1:4]
    plots = sys.argv[4:] or ["geometry", "solve", "stiffness", "tolerance", "efficiency", "backlash", "mesh", "compare"]
    os.makedirs(out_dir, exist_ok=True)
    failures, written, skipped = [], 0, []
    for deck in decks(cases_dir):
        name = os.path.relpath(deck, cases_dir).replace("/", "_")[:-5]
        text = open(deck, encoding="utf-8").read()
        discs = 2 if "[second_disc]" in text else 1
        for plot in plots:
            svg = os.path.join(out_dir, f"{name}_{plot}.svg")
            if plot == "geometry":
                cmd = [ltca, "geometry", deck, "--svg", svg, "--crank-deg", "3"]
                ok_codes = (0,)
            elif plot in COMMANDS:
                args, ok_codes, section = COMMANDS[plot]
                if section not in text:
                    skipped.append(f"{plot} {deck}: no {section}")
                    continue
                if plot == "stiffness" and re.search(r"^\s*torque_nm\s*=\s*0(\.0*)?\s*$", text, re.M):
                    skipped.append(f"{plot} {deck}: zero torque (no loop to draw)")
                    continue
                if "sweep.positions=" in " ".join(args) and re.search(r"^\s*positions\s*=\s*1\s*$", text, re.M):
                    args = [a for a in args if a not in ("--set",) and not a.startswith("sweep.positions=")]
                cmd = [ltca, plot, deck, "--svg", svg] + args
            else:
                if "[material]" not in text:  # a geometry-only deck (Chen 2008): nothing to solve
                    skipped.append(f"solve {deck}: no [material]")
                    continue
                # Five positions keep it fast; a deck of one crank angle keeps its one position.
                single = re.search(r"^\s*positions\s*=\s*1\s*$", text, re.M)
                cmd = [ltca, "solve", deck, "--svg", svg] + ([] if single else ["--set", "sweep.positions=5"])
                ok_codes = (0, 1)  # 1: a position did not succeed (cases/hard); the figure is still due
            if os.path.exists(svg):
                os.remove(svg)
            run = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            try:
                expect(run.returncode in ok_codes, f"exit {run.returncode}: {run.stderr.strip()[-300:]}")
                if plot == "geometry":
                    check_geometry(svg, deck)
                elif plot == "solve":
                    check_solve(svg, deck, discs)
                else:
                    CHECKS[plot](svg, deck, run.returncode)
                written += 1
            except (AssertionError, ET.ParseError, OSError, AttributeError) as e:
                failures.append(f"{plot} {deck}: {e}")
    for f in failures:
        print("FAIL", f)
    for s in skipped:
        print("not applicable:", s)
    print(f"{written} figures checked, {len(skipped)} not applicable, {len(failures)} failures")
    return 1 if failures or written == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
