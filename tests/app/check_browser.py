#!/usr/bin/env python3
"""Issue 27: the report in a real browser (headless Chromium, Debian `chromium`).

    check_browser.py LTCA OUT_DIR DECK [--set section.key=value ...]

Runs `ltca report DECK -o OUT_DIR`, then opens OUT_DIR/index.html in headless Chromium 1,400 px
wide and fails on:
- any console message of the page (it has no script: a message is an error of the page);
- a broken image (an <img> that did not load) or an inline figure (<svg>) of zero width or height;
- a page wider than the window (horizontal scrolling at 1,400 px);
- a screenshot (OUT_DIR/report.png) that Chromium did not write, or that is blank.
The layout is measured by a probe page beside the report that loads it in a 1,400 px frame and
writes what it measured into its own DOM, which `--dump-dom` prints (file access between the two
local pages allowed by --allow-file-access-from-files).

A Chromium that has not finished after HANG_GUARD seconds (over 30x its run on a quiet machine, a
few seconds) is killed and reported as "too slow", a failure apart from a wrong page (exit 3, not
1): a hang, or a machine far too loaded, never a verdict on the report (issue 55).

Without Chromium the test says so and exits 77, which ctest counts as skipped (SKIP_RETURN_CODE),
never as passed.
"""
import json
import os
import re
import shutil
import subprocess
import sys

WIDTH = 1400
HANG_GUARD = 300  # seconds of wall time; a hang guard, not a verdict


class TooSlow(Exception):
    pass

PROBE = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>probe</title></head>
<body style="margin:0">
<iframe id="page" src="index.html" style="border:0;width:%(width)dpx;height:2000px"></iframe>
<pre id="result">pending</pre>
<script>
document.getElementById("page").addEventListener("load", function () {
  var frame = document.getElementById("page");
  var doc = frame.contentDocument;
  var out = {};
  if (!doc) { out.error = "the report's document is not readable"; }
  else {
    var root = doc.documentElement;
    out.scroll_width = root.scrollWidth;
    out.client_width = root.clientWidth;
    out.images = doc.images.length;
    out.broken_images = [];
    for (var i = 0; i < doc.images.length; ++i) {
      var im = doc.images[i];
      if (!im.complete || im.naturalWidth === 0) out.broken_images.push(im.getAttribute("src"));
    }
    var svgs = doc.querySelectorAll("body svg");
    out.figures = 0;
    out.empty_figures = [];
    for (var k = 0; k < svgs.length; ++k) {
      if (svgs[k].parentElement && svgs[k].parentElement.closest("svg")) continue;  // nested
      out.figures += 1;
      var r = svgs[k].getBoundingClientRect();
      if (!(r.width > 0 && r.height > 0)) out.empty_figures.push(k);
    }
    out.sections = doc.querySelectorAll("h2").length;
  }
  document.getElementById("result").textContent = JSON.stringify(out);
});
</script>
</body></html>
"""


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def run_browser(browser, args):
    base = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
            "--disable-extensions", "--enable-logging=stderr", "--v=0", f"--window-size={WIDTH},2000"]
    try:
        return subprocess.run(base + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              timeout=HANG_GUARD)
    except subprocess.TimeoutExpired as e:
        raise TooSlow(f"Chromium had not finished after {HANG_GUARD} s: {' '.join(args)}") from e


def main():
    ltca, out_dir, deck = sys.argv[1:4]
    sets = sys.argv[4:]
    browser = chromium()
    if browser is None:
        print("SKIPPED: no Chromium on this machine (Debian package `chromium`); the browser test did not run")
        return 77
    run = subprocess.run([ltca, "report", deck, *sets, "-o", out_dir], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    if run.returncode != 0:
        print(f"FAIL ltca report exit {run.returncode}: {run.stderr[-400:]}")
        return 1
    failures = []
    page = os.path.abspath(os.path.join(out_dir, "index.html"))
    shot = os.path.abspath(os.path.join(out_dir, "report.png"))
    if os.path.exists(shot):
        os.remove(shot)
    # The page itself: its console, and the screenshot.
    direct = run_browser(browser, [f"--screenshot={shot}", "file://" + page])
    console = [line for line in direct.stderr.splitlines() if ":CONSOLE" in line]
    failures += [f"console: {line}" for line in console]
    if not os.path.exists(shot):
        failures.append("Chromium wrote no screenshot")
    elif os.path.getsize(shot) < 20_000:
        failures.append(f"the screenshot is {os.path.getsize(shot)} bytes: a blank page?")
    # The layout, measured by the probe.
    probe = os.path.abspath(os.path.join(out_dir, "browser_probe.html"))
    with open(probe, "w", encoding="utf-8") as f:
        f.write(PROBE % {"width": WIDTH})
    measured = run_browser(browser, ["--allow-file-access-from-files", "--virtual-time-budget=20000", "--dump-dom",
                                     "file://" + probe])
    failures += [f"console (probe): {line}" for line in measured.stderr.splitlines() if ":CONSOLE" in line]
    match = re.search(r'<pre id="result">(.*?)</pre>', measured.stdout, re.S)
    if not match or match.group(1) == "pending":
        failures.append("the probe measured nothing (the report did not load in the frame)")
    else:
        m = json.loads(match.group(1).replace("&quot;", '"').replace("&amp;", "&"))
        if "error" in m:
            failures.append(m["error"])
        else:
            if m["scroll_width"] > m["client_width"]:
                failures.append(f"the page scrolls sideways at {WIDTH} px: {m['scroll_width']} px wide")
            if m["broken_images"]:
                failures.append(f"broken images: {m['broken_images']}")
            if m["empty_figures"]:
                failures.append(f"figures of zero size: {m['empty_figures']} of {m['figures']}")
            if m["figures"] == 0:
                failures.append("no figure on the page")
            print(f"measured at {WIDTH} px: {m['scroll_width']} px wide, {m['figures']} figures, {m['images']} images, "
                  f"{m['sections']} sections")
    os.remove(probe)
    for f in failures:
        print("FAIL", f)
    print(f"screenshot {shot}, {len(console)} console messages, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except TooSlow as e:
        print(f"TOO SLOW (the hang guard, not a wrong page): {e}")
        sys.exit(3)
