#!/usr/bin/env python3
"""Issue 16: `ltca report DECK -o DIR` writes one static page that a browser opens from disk.

    check_report.py LTCA OUT_DIR [DECK [FIGURES [WORD ...]]]

FIGURES: the number of inline figures expected (default 5); WORD: further text the page must hold
(a deck with [friction] adds the efficiency figure, one with [tolerances] the histograms); a WORD
"--set=section.key=value" is passed to ltca report as --set instead (the inputs table then holds
the key too).

Issue 27: the page has a contents list of its sections, each section present (or a one-line note
why not); its inputs table lists every key the deck gives (read here with tomllib, --set keys
included) as a row whose data-key is "section.key"; the allowables table holds the contact stress
row and one row per [tolerances] limit, each with a verdict (pass, FAIL, or no allowable / n/a).

Checked: exit 0; DIR/index.html parses as HTML (html.parser) with no external resource (no
script, stylesheet, image or frame fetched from anywhere: nothing but inline content); it names
the case, the model and the solver; it holds the geometry table and the summaries; its five
figures (geometry, solve, backlash, mesh, the stiffness loop) are inline SVGs, each parsed with xml.etree.ElementTree and carrying its axis labels;
the SVG element ids are unique in the page (several PLplot figures in one page).
"""
import html.parser
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"
LTCA = "{urn:ltca:plots}"


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.fetches, self.tags, self.text = [], [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        for name, value in attrs:
            if name in ("src", "href", "data", "srcset", "poster") and value and not value.startswith("#"):
                self.fetches.append(f"<{tag} {name}={value}>")
        if tag in ("script", "link", "iframe", "object", "embed", "img"):
            self.fetches.append(f"<{tag}>")

    def handle_data(self, data):
        self.text.append(data)


def main():
    ltca, out_dir = sys.argv[1:3]
    deck = sys.argv[3:4]
    expected = int(sys.argv[4]) if len(sys.argv) > 4 else 5
    extra = [w for w in sys.argv[5:] if not w.startswith("--set=")]
    sets = [w[len("--set="):] for w in sys.argv[5:] if w.startswith("--set=")]
    options = [x for s in sets for x in ("--set", s)]
    run = subprocess.run([ltca, "report", *deck, *options, "-o", out_dir], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    failures = []
    if run.returncode != 0:
        print(f"FAIL exit {run.returncode}: {run.stderr[-400:]}")
        return 1
    page_text = open(os.path.join(out_dir, "index.html"), encoding="utf-8").read()
    page = Page()
    page.feed(page_text)
    if page.fetches:
        failures.append(f"the page fetches: {page.fetches[:5]}")
    text = " ".join(page.text)
    for word in ("Contents", "Inputs", "Results against allowables", "model", "solver", "Geometry", "mean TE (arcsec)",
                 "peak-to-peak TE (arcsec)", "mean backlash (arcsec)", "z_p (pins)", "torsional rigidity (N*m/arcmin)",
                 "Torsional stiffness", "Friction and meshing efficiency", "Tolerance analysis (Monte Carlo)", *extra):
        if word not in text:
            failures.append(f"'{word}' is not on the page")
    for raw in ("wall_seconds", "wall seconds", "tip_relief.land_half_width_mm"):
        if raw in text:
            failures.append(f"the raw key '{raw}' is on the page")
    # Every section of the contents is on the page.
    for anchor in re.findall(r'<a href="#([a-z]+)">', page_text):
        if f'id="{anchor}"' not in page_text:
            failures.append(f"the contents link #{anchor} has no section")
    # The inputs table against the deck's own keys (issue 27's must-show).
    import tomllib
    deck_path = deck[0] if deck else None
    if deck_path:
        with open(deck_path, "rb") as f:
            given = tomllib.load(f)
        for s in sets:
            key, value = s.split("=", 1)
            section, name = key.split(".", 1)
            try:  # as ltca reads --set: a TOML value, or else a bare string
                value = tomllib.loads(f"v = {value}")["v"]
            except tomllib.TOMLDecodeError:
                pass
            given.setdefault(section, {})[name] = value
        inputs = page_text[page_text.find('id="inputs"'):page_text.find('id="allowables"')]
        rows = set(re.findall(r'<tr data-key="([^"]+)"', inputs))
        for section, table in given.items():
            for name in table:
                if f"{section}.{name}" not in rows:
                    failures.append(f"the inputs table has no row for [{section}] {name}")
        allowables = page_text[page_text.find('id="allowables"'):page_text.find('id="geometry"')]
        verdicts = dict(re.findall(r'<tr data-key="([^"]+)">(?:<t[hd]>.*?</t[hd]>){4}<td>(.*?)</td>', allowables))
        wanted = ["max_contact_stress_mpa"] + list(given.get("tolerances", {}).get("limits", {}))
        for figure in wanted:
            if figure not in verdicts:
                failures.append(f"the allowables table has no row for {figure}")
            elif not re.search(r"pass|FAIL|no allowable|n/a", verdicts[figure]):
                failures.append(f"the allowables row of {figure} has no verdict: {verdicts[figure]!r}")
    svgs = re.findall(r"<svg\b.*?</svg>", page_text, re.S)
    # The sections of the table's generic analyses (one each, after the fixed ones) are counted apart:
    # a new analysis adds its own figure to every page it runs for.
    blocks = re.findall(r'<div class="analysis" data-analysis="([^"]+)">(.*?)</div><!-- end of analysis \1 -->', page_text, re.S)
    for name, block in blocks:
        if not re.search(r'<tr data-key="|<svg\b', block):
            failures.append(f"the section of the analysis {name} holds neither key figures nor a figure")
    if len(svgs) - sum(len(re.findall(r"<svg\b", block)) for _, block in blocks) != expected:
        failures.append(f"{len(svgs)} inline figures, expected {expected} (geometry, solve, backlash, mesh, stiffness loop, "
                        "and efficiency / tolerance when the deck has them)")
    ids = re.findall(r'\bid="([^"]+)"', page_text)
    if len(ids) != len(set(ids)):
        failures.append("element ids repeat across the figures")
    for k, svg in enumerate(svgs):
        try:
            root = ET.fromstring(svg)
            drawn = ["".join(t.itertext()) for t in root.iter(SVG + "text")]
            panels = root.findall(f"{SVG}metadata/{LTCA}figure/{LTCA}panel")
            if not panels:
                failures.append(f"figure {k}: no panels in its metadata")
            for p in panels:
                for axis in ("x_label", "y_label"):
                    if p.get(axis) not in drawn:
                        failures.append(f"figure {k}: the {axis} '{p.get(axis)}' is not drawn")
        except ET.ParseError as e:
            failures.append(f"figure {k}: not well-formed: {e}")
    for f in failures:
        print("FAIL", f)
    print(f"{len(svgs)} figures, {len(page.fetches)} fetches, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
