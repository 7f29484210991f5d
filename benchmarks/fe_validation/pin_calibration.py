#!/usr/bin/python3
"""The pin of the CalculiX model (liu52_ccx.py): which rigid core gives ltca's pin term.

ltca's hertz-line law counts the pin's own approach as (Liu 2021 eq. 22-25)
    delta_p = (2 F / (pi B)) C_p (ln(4 r_p / b) - 1/2),   C_p = (1 - nu^2) / E,
the approach of the pin centre to the contact's centre. The FE pin is an elastic annulus (outer
radius r_p = 3 mm) whose inner circle of radius a is held (a rigid core). Its approach is the
normal displacement of the surface point at the centre of a Hertzian (elliptic) pressure of
half-width b and resultant F. Both share the Hertz local part (-(2F/(pi B)) C_p ln b); they differ
by a constant of the far field, fixed by a. This script loads the FE annulus by that pressure for
a few core radii and a few b and prints the FE approach beside the formula, and the core radius
for which they agree (interpolated in ln a).

Run: /usr/bin/python3 benchmarks/fe_validation/pin_calibration.py --out /tmp/cx/pin
The stage's output pins (r_w = 5 mm, stage_ccx.py):
     /usr/bin/python3 benchmarks/fe_validation/pin_calibration.py --radius 5 --cores 0.6,1.0,1.5 \
         --bs 0.1,0.325 --h0 0.005 --out /tmp/cx/opin
"""
import argparse
import math
import os
import subprocess

import numpy as np

E_MOD, NU, B, R = 206000.0, 0.3, 12.0, 3.0


def run(core, b, force, h0, out):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    geo = gmsh.model.geo

    def circle(r):
        cp = geo.addPoint(0, 0, 0)
        ps = [geo.addPoint(r * math.cos(t), r * math.sin(t), 0) for t in (0, 0.5 * math.pi, math.pi, 1.5 * math.pi)]
        return [geo.addCircleArc(ps[i], cp, ps[(i + 1) % 4]) for i in range(4)]

    outer, inner = circle(R), circle(core)
    s = geo.addPlaneSurface([geo.addCurveLoop(outer), geo.addCurveLoop(inner)])
    lp = geo.addPoint(R, 0, 0)  # the load point: +x
    geo.synchronize()
    f = gmsh.model.mesh.field
    d = f.add("Distance")
    f.setNumbers(d, "PointsList", [lp])
    t = f.add("Threshold")
    f.setNumber(t, "InField", d)
    f.setNumber(t, "SizeMin", h0)
    f.setNumber(t, "SizeMax", 0.1 * R)
    f.setNumber(t, "DistMin", 2.5 * b)
    f.setNumber(t, "DistMax", 2.5 * b + (0.1 * R - h0) / 0.25)
    f.setAsBackgroundMesh(t)
    for k in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber("Mesh." + k, 0)
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(2)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    x = coords.reshape(-1, 3)[:, :2].copy()
    idx = {int(tg): i for i, tg in enumerate(tags)}
    _, _, conn = gmsh.model.mesh.getElements(2, s)
    el = np.vectorize(idx.get)(conn[0].reshape(-1, 6).astype(np.int64))

    def cn(cs):
        out_ = set()
        for c in cs:
            nt, _, _ = gmsh.model.mesh.getNodes(1, c, includeBoundary=True)
            out_.update(idx[int(v)] for v in nt)
        return sorted(out_)

    on, inn = cn(outer), cn(inner)
    gmsh.finalize()
    for nodes, r in ((on, R), (inn, core)):
        x[nodes] *= r / np.linalg.norm(x[nodes], axis=1, keepdims=True)
    a = x[el[:, 1]] - x[el[:, 0]]
    bb = x[el[:, 2]] - x[el[:, 0]]
    neg = (a[:, 0] * bb[:, 1] - a[:, 1] * bb[:, 0]) < 0
    el[neg] = el[neg][:, [0, 2, 1, 5, 4, 3]]
    ons = set(on)
    # faces under the pressure, p(s) = p0 sqrt(1 - s^2 / b^2) at the face's mid node (arc length s)
    p0 = 2 * force / (math.pi * b * B)
    loads, ftot = [], 0.0
    for i, e in enumerate(el):
        for fi, (p, q, m) in enumerate(((0, 1, 3), (1, 2, 4), (2, 0, 5))):
            if e[p] in ons and e[q] in ons and e[m] in ons:
                sm = R * math.atan2(x[e[m], 1], x[e[m], 0])
                if abs(sm) < b:
                    pr = p0 * math.sqrt(1 - (sm / b) ** 2)
                    ln = R * abs(math.atan2(x[e[q], 1], x[e[q], 0]) - math.atan2(x[e[p], 1], x[e[p], 0]))
                    loads.append((i + 1, fi + 1, pr))
                    ftot += pr * ln * B
    centre = min(on, key=lambda n: np.linalg.norm(x[n] - np.array([R, 0.0])))
    lines = ["*NODE, NSET=NALL"] + ["%d,%.12f,%.12f" % (i + 1, p[0], p[1]) for i, p in enumerate(x)]
    lines += ["*ELEMENT, TYPE=CPE6, ELSET=PIN"] + ["%d,%s" % (i + 1, ",".join(str(n + 1) for n in e)) for i, e in enumerate(el)]
    lines += ["*NSET, NSET=CORE"] + [str(n + 1) for n in inn]
    lines += ["*NSET, NSET=C", str(centre + 1)]
    lines += ["*MATERIAL, NAME=S", "*ELASTIC", "%g,%g" % (E_MOD, NU), "*SOLID SECTION, ELSET=PIN, MATERIAL=S", "%g" % B]
    lines += ["*BOUNDARY", "CORE,1,2,0.", "*STEP", "*STATIC", "*DLOAD"] + ["%d,P%d,%.9g" % l for l in loads]
    lines += ["*NODE PRINT, NSET=C", "U", "*NODE PRINT, NSET=CORE, TOTALS=ONLY", "RF", "*END STEP"]
    os.makedirs(out, exist_ok=True)
    open(os.path.join(out, "pin.inp"), "w").write("\n".join(lines) + "\n")
    subprocess.run(["ccx", "-i", "pin"], cwd=out, stdout=subprocess.DEVNULL, env=dict(os.environ, OMP_NUM_THREADS="1"))
    txt = open(os.path.join(out, "pin.dat")).read().split("\n")
    u = rf = None
    for i, ln in enumerate(txt):
        if "displacements" in ln:
            u = -float(txt[i + 2].split()[1])  # inward, along -x
        if "total force" in ln:
            rf = float(txt[i + 2].split()[0])
    c = (1 - NU ** 2) / E_MOD
    formula = 2 * rf / (math.pi * B) * c * (math.log(4 * R / b) - 0.5)
    return u, formula, rf, len(x)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--h0", type=float, default=0.002)
    ap.add_argument("--force", type=float, default=1000.0)
    ap.add_argument("--cores", default="0.3,0.6,1.0,1.5")
    ap.add_argument("--bs", default="0.03,0.06")
    ap.add_argument("--radius", type=float, default=3.0, help="the pin's outer radius, mm")
    a = ap.parse_args()
    global R
    R = a.radius
    print("core_mm  b_mm  F_N(reaction)  nodes  FE_approach_um  ltca_pin_term_um  FE/ltca")
    for b in [float(v) for v in a.bs.split(",")]:
        res = []
        for core in [float(v) for v in a.cores.split(",")]:
            u, fo, rf, n = run(core, b, a.force, a.h0, os.path.join(a.out, "c%g_b%g" % (core, b)))
            print("%.3f  %.3f  %.2f  %d  %.5f  %.5f  %.4f" % (core, b, rf, n, u * 1e3, fo * 1e3, u / fo))
            res.append((core, u - fo))
        for (c1, d1), (c2, d2) in zip(res, res[1:]):
            if d1 * d2 <= 0:
                w = d1 / (d1 - d2)
                print("b = %g: FE = ltca at core radius %.4f mm" % (b, math.exp(math.log(c1) + w * (math.log(c2) - math.log(c1)))))


if __name__ == "__main__":
    main()
