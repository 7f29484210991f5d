#!/usr/bin/python3
"""A plane-strain CalculiX contact model of Liu's section 5.2 pair (cases/liu2021_sec52_base.toml).

The reference for ltca's elastic disc (issue 48). Independent of ltca's code: the profile and the
kinematics are written here again from Liu 2021 eq. 1, 14, 15 (docs/conventions.md), the mesh is
gmsh's (Python API), the solve CalculiX's (ccx 2.20).

Model
  - the disc: its real modified profile (generating radii R_p + dR_p = 63.983, r_rp + dR_rp =
    2.996 mm, e = 1.3, 39 teeth), a central bore of radius --bore whose nodes follow a rigid
    rotation psi about the disc centre (the centre's translation held): the rotation is
    prescribed, the torque is the bore's reaction moment (displacement control); --psi sets
    the solved rotations, and the rotation at --torque is interpolated linearly between the two
    that bracket it (tabulate.py adds the quadratic through the three nearest);
  - the pins: elastic annuli, outer radius 3 mm at the nominal pin circle 64 mm, the inner
    circle (radius --core, default 0.606 mm) held: a rigid core. 0.606 mm makes the pin's own
    approach ltca's pin term (2F / (pi B)) C_p (ln(4 r_p / b) - 1/2) (pin_calibration.py);
  - plane strain, thickness B = 12 mm, E = 206,000 MPa, nu = 0.3 for both;
  - frictionless face-to-face penalty contact (CalculiX SURFACE TO SURFACE,
    linear pressure-overclosure of slope --penalty), small displacements (no NLGEOM);
  - quadratic 6-node triangles (CPE6), gmsh Frontal-Delaunay, sized by the distance to the
    contact points: --h0 within --d0 of each, growing by --grow per mm to --hdisc in the disc
    and --hpin in the pins; every node on the outline, the pin circles, the cores and the bore
    is moved onto the exact curve after meshing.
  - --local D: the disc elastic only within D mm of the contact points; beyond, E x 1000.

Run (the machine's python has numpy and gmsh: /usr/bin/python3; apt-get install
calculix-ccx gmsh python3-gmsh):
  /usr/bin/python3 benchmarks/fe_validation/liu52_ccx.py --crank-deg 0 --bore 22 --h0 0.01 \
      --refine 3,4,5,6,7,8,9 --psi 22:26:2 --first-inc 0.5 --out /tmp/cx/b22c0
(one ccx thread; 10-30 min on a shared 2-core machine; run_all.sh has every run of the docs)
prints one JSON document (also written to OUT/result.json): the rigid first-contact rotation,
the torque-rotation samples, the rotation at 206 N*m, TE, pin forces, the largest pressure,
the penetration, the mesh size and the run time. Nothing is written under the repository.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

# Liu 2021 section 5.2 pair (cases/liu2021_sec52_base.toml)
ZP, ZC = 40, 39
RP, RRP = 64.0, 3.0            # pins as made: nominal
DRP, DRRP = -0.017, -0.004     # the disc's modification
E_ECC = 1.3
B = 12.0
E_MOD, NU = 206000.0, 0.3
ARCSEC = math.pi / 180.0 / 3600.0

RG = RP + DRP                  # generating pin-circle radius 63.983
RG_PIN = RRP + DRRP            # generating pin radius 2.996
ZE = ZP / 1.0                  # z_p / d, d = 1


# --- the profile (body frame), Liu eq. 1 / docs/conventions.md ---------------------------------
def locus(u):
    u = np.asarray(u, dtype=float)
    q = np.stack([RG * np.cos(u) - E_ECC * np.cos(ZE * u), RG * np.sin(u) - E_ECC * np.sin(ZE * u)], -1)
    q1 = np.stack([-RG * np.sin(u) + E_ECC * ZE * np.sin(ZE * u), RG * np.cos(u) - E_ECC * ZE * np.cos(ZE * u)], -1)
    return q, q1


def profile(u):
    """Point and outward normal of the reference tooth space (k = 0) at parameter u."""
    q, q1 = locus(u)
    t = q1 / np.linalg.norm(q1, axis=-1, keepdims=True)
    n_in = np.stack([-t[..., 1], t[..., 0]], -1)
    return q + RG_PIN * n_in, -n_in


def rot(v, a):
    c, s = math.cos(a), math.sin(a)
    v = np.asarray(v, dtype=float)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], -1)


HALF = math.pi / ZC            # phi_max for |d| = 1


def project_to_profile(p_body):
    """Nearest points of the real profile to body-frame points p (n x 2): (points, normals, k, u)."""
    p = np.atleast_2d(p_body)
    ang = np.arctan2(p[:, 1], p[:, 0])
    k = np.round(ang / (2 * HALF)).astype(int) % ZC
    loc = np.stack([rot(p[i], -2 * HALF * k[i]) for i in range(len(p))]) if len(p) else p
    us = np.linspace(-HALF, HALF, 4001)
    xs, _ = profile(us)
    # initial guess: nearest sample
    u = np.empty(len(p))
    for i in range(len(p)):
        u[i] = us[np.argmin(np.sum((xs - loc[i]) ** 2, axis=1))]
    for _ in range(30):  # Newton on g(u) = (x(u) - p) . q1(u) (the normal through p)
        x, _n = profile(u)
        _, q1 = locus(u)
        g = np.sum((x - loc) * q1, axis=1)
        h = 1e-7
        x2, _ = profile(u + h)
        _, q12 = locus(u + h)
        g2 = np.sum((x2 - loc) * q12, axis=1)
        du = -g / ((g2 - g) / h)
        u = np.clip(u + du, -HALF, HALF)
        if np.max(np.abs(du)) < 1e-15:
            break
    x, n = profile(u)
    xb = np.stack([rot(x[i], 2 * HALF * k[i]) for i in range(len(p))])
    nb = np.stack([rot(n[i], 2 * HALF * k[i]) for i in range(len(p))])
    return xb, nb, k, u


# --- kinematics (Liu eq. 14, 15): d = 1 -----------------------------------------------------------
def pose(crank):
    return np.array([E_ECC * math.cos(crank), E_ECC * math.sin(crank)]), -crank / ZC


def pin_centre(j):  # j = 0 .. 39 (printed j + 1)
    a = 2 * math.pi * j / ZP
    return np.array([RP * math.cos(a), RP * math.sin(a)])


def mesh_state(crank, pins):
    """Per pin: contact point (fixed frame), outward normal, clearance (mm), arm (mm)."""
    oc, th = pose(crank)
    out = {}
    for j in pins:
        pc = pin_centre(j)
        pb = rot(pc - oc, -th)
        xb, nb, k, u = project_to_profile(pb[None, :])
        x = oc + rot(xb[0], th)
        n = rot(nb[0], th)
        dist = np.linalg.norm(pc - x)
        side = np.dot(pc - x, n)
        gap = (dist if side > 0 else -dist) - RRP
        r = x - oc
        arm = r[0] * n[1] - r[1] * n[0]
        out[j] = dict(point=x, normal=n, gap=gap, arm=arm, k=int(k[0]), u=float(u[0]),
                      pin_point=pc - RRP * (pc - x) / dist)
    return out


# --- the mesh (gmsh) ---------------------------------------------------------------------------
def build_mesh(a, state, refined_pins):
    import gmsh
    oc, th = pose(a.crank)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.model.add("liu52")
    geo = gmsh.model.geo
    # disc outline: one spline per tooth space
    npts = a.spline_points
    us = np.linspace(-HALF, HALF, npts + 1)
    xs, _ = profile(us)
    first = None
    prev_end = None
    curves = []
    for k in range(ZC):
        pts = oc + rot(rot(xs, 2 * HALF * k), th)
        tags = []
        for i in range(npts + 1):
            if i == 0 and prev_end is not None:
                tags.append(prev_end)
                continue
            if k == ZC - 1 and i == npts:
                tags.append(first)
                continue
            tags.append(geo.addPoint(pts[i, 0], pts[i, 1], 0.0))
        if first is None:
            first = tags[0]
        prev_end = tags[-1]
        curves.append(geo.addSpline(tags))
    outline_loop = geo.addCurveLoop(curves)

    def circle(c, r):
        cp = geo.addPoint(c[0], c[1], 0.0)
        ps = [geo.addPoint(c[0] + r * math.cos(t), c[1] + r * math.sin(t), 0.0) for t in (0, 0.5 * math.pi, math.pi, 1.5 * math.pi)]
        arcs = [geo.addCircleArc(ps[i], cp, ps[(i + 1) % 4]) for i in range(4)]
        return arcs

    bore_arcs = circle(oc, a.bore)
    disc_surf = geo.addPlaneSurface([outline_loop, geo.addCurveLoop(bore_arcs)])
    pin_surf, pin_outer, pin_core = {}, {}, {}
    for j in state:
        pc = pin_centre(j)
        outer = circle(pc, RRP)
        core = circle(pc, a.core)
        pin_outer[j], pin_core[j] = outer, core
        pin_surf[j] = geo.addPlaneSurface([geo.addCurveLoop(outer), geo.addCurveLoop(core)])
    # size-field points: the contact points of the refined pins (disc side and pin side)
    fpts = []
    for j in refined_pins:
        for p in (state[j]["point"], state[j]["pin_point"]):
            fpts.append(geo.addPoint(p[0], p[1], 0.0))
    geo.synchronize()
    f = gmsh.model.mesh.field
    dist = f.add("Distance")
    f.setNumbers(dist, "PointsList", fpts)

    def threshold(hmax):
        t = f.add("Threshold")
        f.setNumber(t, "InField", dist)
        f.setNumber(t, "SizeMin", a.h0)
        f.setNumber(t, "SizeMax", hmax)
        f.setNumber(t, "DistMin", a.d0)
        f.setNumber(t, "DistMax", a.d0 + (hmax - a.h0) / a.grow)
        return t

    td, tp = threshold(a.hdisc), threshold(a.hpin)
    rd = f.add("Restrict")
    f.setNumber(rd, "InField", td)
    f.setNumbers(rd, "SurfacesList", [disc_surf])
    f.setNumbers(rd, "CurvesList", curves + bore_arcs)
    rp = f.add("Restrict")
    f.setNumber(rp, "InField", tp)
    f.setNumbers(rp, "SurfacesList", list(pin_surf.values()))
    f.setNumbers(rp, "CurvesList", [c for j in state for c in pin_outer[j] + pin_core[j]])
    mn = f.add("Min")
    f.setNumbers(mn, "FieldsList", [rd, rp])
    f.setAsBackgroundMesh(mn)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Algorithm", a.algorithm)
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(2)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = coords.reshape(-1, 3)[:, :2]
    idx = {int(t): i for i, t in enumerate(tags)}

    def tris(surf):
        types, _, conn = gmsh.model.mesh.getElements(2, surf)
        assert list(types) == [9], types
        return np.vectorize(idx.get)(conn[0].reshape(-1, 6).astype(np.int64))

    def curve_nodes(cs):
        s = set()
        for c in cs:
            nt, _, _ = gmsh.model.mesh.getNodes(1, c, includeBoundary=True)
            s.update(idx[int(t)] for t in nt)
        return np.array(sorted(s))

    mesh = dict(xyz=xyz.copy(), disc=tris(disc_surf), pins={j: tris(pin_surf[j]) for j in state},
                outline=curve_nodes(curves), bore=curve_nodes(bore_arcs),
                pin_outer={j: curve_nodes(pin_outer[j]) for j in state},
                pin_core={j: curve_nodes(pin_core[j]) for j in state})
    gmsh.finalize()
    # exact curves
    x = mesh["xyz"]
    ob = mesh["outline"]
    pb = rot(x[ob] - oc, -th)
    xb, _, _, _ = project_to_profile(pb)
    moved = np.max(np.linalg.norm(xb - pb, axis=1))
    x[ob] = oc + rot(xb, th)

    def onto_circle(nodes, c, r):
        d = x[nodes] - c
        x[nodes] = c + r * d / np.linalg.norm(d, axis=1, keepdims=True)

    onto_circle(mesh["bore"], oc, a.bore)
    for j in state:
        onto_circle(mesh["pin_outer"][j], pin_centre(j), RRP)
        onto_circle(mesh["pin_core"][j], pin_centre(j), a.core)
    mesh["outline_moved_mm"] = float(moved)
    return mesh


def orient(el, x):
    a = x[el[:, 1]] - x[el[:, 0]]
    b = x[el[:, 2]] - x[el[:, 0]]
    neg = (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) < 0
    el = el.copy()
    el[neg] = el[neg][:, [0, 2, 1, 5, 4, 3]]
    return el


def faces_on(el, nodes, x, centre, radius, first_id):
    """(element id, face) of the edges of el whose three nodes lie in `nodes` within radius of centre."""
    ns = set(int(n) for n in nodes)
    out = []
    for i, e in enumerate(el):
        for f, (p, q, m) in enumerate(((0, 1, 3), (1, 2, 4), (2, 0, 5))):
            if e[p] in ns and e[q] in ns and e[m] in ns and np.linalg.norm(x[e[m]] - centre) < radius:
                out.append((first_id + i, f + 1))
    return out


# --- CalculiX deck -----------------------------------------------------------------------------------
def write_deck(path, a, mesh, state, psi_steps):
    x = mesh["xyz"]
    oc, _ = pose(a.crank)
    lines = ["** Liu 2021 sec. 5.2 pair, plane strain, written by benchmarks/fe_validation/liu52_ccx.py",
             "*NODE, NSET=NALL"]
    lines += ["%d,%.12f,%.12f" % (i + 1, p[0], p[1]) for i, p in enumerate(x)]
    disc = orient(mesh["disc"], x)
    eid = 1
    # the disc, split into elastic and (for --local) stiff elements
    cen = x[disc[:, :3]].mean(axis=1)
    if a.local > 0:
        cps = np.array([state[j]["point"] for j in state])
        dmin = np.min(np.linalg.norm(cen[:, None, :] - cps[None, :, :], axis=2), axis=1)
        soft = dmin < a.local
    else:
        soft = np.ones(len(disc), bool)
    disc_first = eid
    groups = [("DISC", disc[soft], eid)]
    eid += int(soft.sum())
    if (~soft).any():
        groups.append(("DISCSTIFF", disc[~soft], eid))
        eid += int((~soft).sum())
    # reorder disc so ids of groups match: surfaces need element ids
    disc_all = np.concatenate([g[1] for g in groups])
    pin_first = {}
    for j in state:
        el = orient(mesh["pins"][j], x)
        groups.append(("PIN%d" % (j + 1), el, eid))
        pin_first[j] = eid
        eid += len(el)
    for name, el, first in groups:
        lines.append("*ELEMENT, TYPE=CPE6, ELSET=%s" % name)
        lines += ["%d,%s" % (first + i, ",".join(str(int(n) + 1) for n in e)) for i, e in enumerate(el)]
    lines.append("*NSET, NSET=BORE")
    lines += [str(int(n) + 1) for n in mesh["bore"]]
    for j in state:
        lines.append("*NSET, NSET=CORE%d" % (j + 1))
        lines += [str(int(n) + 1) for n in mesh["pin_core"][j]]
    pairs = []
    for j in state:
        c = state[j]["point"]
        sd = faces_on(disc_all, mesh["outline"], x, c, a.surf_radius, disc_first)
        sp = faces_on(orient(mesh["pins"][j], x), mesh["pin_outer"][j], x, c, a.surf_radius, pin_first[j])
        if not sd or not sp:
            continue
        lines.append("*SURFACE, NAME=SD%d, TYPE=ELEMENT" % (j + 1))
        lines += ["%d,S%d" % f for f in sd]
        lines.append("*SURFACE, NAME=SP%d, TYPE=ELEMENT" % (j + 1))
        lines += ["%d,S%d" % f for f in sp]
        pairs.append(j)
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "%g,%g" % (E_MOD, NU)]
    lines += ["*MATERIAL, NAME=STIFF", "*ELASTIC", "%g,%g" % (E_MOD * 1000.0, NU)]
    for name, _, _ in groups:
        lines += ["*SOLID SECTION, ELSET=%s, MATERIAL=%s" % (name, "STIFF" if name == "DISCSTIFF" else "STEEL"), "%g" % B]
    lines += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", "%g" % a.penalty]
    for j in pairs:
        # slave: the disc flank; master: the pin
        lines += ["*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SD%d,SP%d" % (j + 1, j + 1)]
    lines += ["*BOUNDARY"]
    for j in state:
        lines.append("CORE%d,1,2,0." % (j + 1))
    bx = x[mesh["bore"]] - oc
    for si, (psi, ninc) in enumerate(psi_steps):
        lines.append("*STEP, INC=1000")
        if ninc:
            lines += ["*STATIC, DIRECT", "%g,1." % (1.0 / ninc)]
        else:
            lines += ["*STATIC", "%g,1.,1e-5,%g" % (a.first_inc, max(a.first_inc, 0.25))]
        lines.append("*BOUNDARY")
        ps = psi * ARCSEC
        for n, r in zip(mesh["bore"], bx):
            lines.append("%d,1,1,%.12e" % (n + 1, -ps * r[1]))
            lines.append("%d,2,2,%.12e" % (n + 1, ps * r[0]))
        lines += ["*NODE PRINT, NSET=BORE", "RF"]
        for j in state:
            lines += ["*NODE PRINT, NSET=CORE%d, TOTALS=ONLY" % (j + 1), "RF"]
        lines += ["*CONTACT PRINT", "CSTR,CDIS", "*END STEP"]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    return pairs, len(disc), sum(len(mesh["pins"][j]) for j in state)


# --- results -----------------------------------------------------------------------------------------
def ffloat(v):
    """A number of ccx's .dat: also Fortran's 1.0-317 without its E."""
    try:
        return float(v)
    except ValueError:
        return float(re.sub(r"(?<=[0-9.])([+-])", r"E\1", v, count=1))


def parse_dat(path, mesh, state, a):
    oc, _ = pose(a.crank)
    x = mesh["xyz"]
    txt = open(path).read().split("\n")
    recs = {}  # time (step-cumulative index) -> dict
    cur = None
    i = 0
    order = []
    while i < len(txt):
        line = txt[i]
        m = re.search(r"forces \(fx,fy,fz\) for set BORE and time\s+(\S+)", line)
        if m:
            cur = {"torque": 0.0, "pins": {}, "press": 0.0, "pen": 0.0, "time": float(m.group(1)), "faces": {}}
            order.append(cur)
            i += 2
            tq = 0.0
            while i < len(txt) and txt[i].strip():
                f = txt[i].split()
                n = int(f[0]) - 1
                r = x[n] - oc
                tq += r[0] * ffloat(f[2]) - r[1] * ffloat(f[1])
                i += 1
            cur["torque"] = tq / 1000.0  # N*m
            continue
        m = re.search(r"total force \(fx,fy,fz\) for set CORE(\d+) and time", line)
        if m and cur is not None:
            f = txt[i + 2].split()
            cur["pins"][int(m.group(1))] = math.hypot(ffloat(f[0]), ffloat(f[1]))
            i += 3
            continue
        if "contact stress" in line and cur is not None:
            i += 2
            while i < len(txt) and txt[i].strip():
                f = txt[i].split()
                cur["press"] = max(cur["press"], ffloat(f[-3]))
                cur["faces"].setdefault((f[0], f[1]), []).append(ffloat(f[-3]))
                i += 1
            continue
        if "relative contact displacement" in line and cur is not None:
            i += 2
            while i < len(txt) and txt[i].strip():
                f = txt[i].split()
                cur["pen"] = max(cur["pen"], -ffloat(f[-3]))  # ccx prints an overclosure < 0
                i += 1
            continue
        i += 1
    return order


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--crank-deg", type=float, default=0.0)
    ap.add_argument("--bore", type=float, default=22.0, help="bore radius, mm")
    ap.add_argument("--torque", type=float, default=206.0, help="N*m")
    ap.add_argument("--pins", default="2-12", help="pins modelled (printed numbers)")
    ap.add_argument("--refine", default="", help="pins whose contacts are refined (default: all modelled)")
    ap.add_argument("--core", type=float, default=0.606, help="rigid core radius of a pin, mm (0.606: ltca's pin term, pin_calibration.py)")
    ap.add_argument("--h0", type=float, default=0.01, help="element size at the contacts, mm")
    ap.add_argument("--d0", type=float, default=0.12, help="radius of the uniform h0 zone, mm")
    ap.add_argument("--grow", type=float, default=0.25, help="size growth per mm of distance")
    ap.add_argument("--hdisc", type=float, default=1.5, help="largest element in the disc, mm")
    ap.add_argument("--hpin", type=float, default=0.4, help="largest element in a pin, mm")
    ap.add_argument("--spline-points", type=int, default=400)
    ap.add_argument("--algorithm", type=int, default=6)
    ap.add_argument("--penalty", type=float, default=1e9, help="contact slope, MPa/mm")
    ap.add_argument("--surf-radius", type=float, default=0.5, help="contact surfaces within this of the contact point, mm")
    ap.add_argument("--local", type=float, default=0.0, help="disc elastic only within this of the contacts (0: everywhere)")
    ap.add_argument("--psi", default="", help="rotations beyond first contact, arcsec: 'a:b:n' (one increment to 0.5 arcsec before first contact, ramp to a, then n equal increments to b)")
    ap.add_argument("--first-inc", type=float, default=0.1,
                    help="first increment of the ramp to a, a fraction (0.5: two increments; 1 makes ccx take 1 - 1e-6 and then a 1e-6 increment, as costly as a full one)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--reparse", action="store_true", help="read OUT's results again (no mesh, no solve)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    a.crank = math.radians(a.crank_deg)
    lo, hi = [int(v) for v in a.pins.split("-")]
    pins = list(range(lo - 1, hi))
    refine = pins if not a.refine else [int(v) - 1 for v in a.refine.split(",")]
    os.makedirs(a.out, exist_ok=True)
    t0 = time.time()
    state = mesh_state(a.crank, pins)
    loaded = {j: s for j, s in state.items() if s["arm"] > 0}
    psi0 = min(s["gap"] / s["arm"] for s in loaded.values()) / ARCSEC
    first_pin = min(loaded, key=lambda j: loaded[j]["gap"] / loaded[j]["arm"]) + 1
    if a.reparse:
        z = np.load(os.path.join(a.out, "mesh.npz"))
        mesh = dict(xyz=z["xyz"], outline_moved_mm=float(z["moved"]))
        info = json.load(open(os.path.join(a.out, "info.json")))
    else:
        mesh = build_mesh(a, state, refine)
    t_mesh = time.time() - t0
    if a.psi:
        p1, p2, n = a.psi.split(":")
        steps = [(psi0 - 0.5, 1), (psi0 + float(p1), 0), (psi0 + float(p2), int(n))]
    else:
        steps = [(psi0 + 40.0, 0)]
    if a.reparse:
        pairs, n_disc, n_pin, rc, t_ccx, t_mesh = [info[k] for k in ("pairs", "n_disc", "n_pin", "rc", "t_ccx", "t_mesh")]
        steps = [tuple(v) for v in info["steps"]]
    else:
        pairs, n_disc, n_pin = write_deck(os.path.join(a.out, "liu52.inp"), a, mesh, state, steps)
        np.savez(os.path.join(a.out, "mesh.npz"), xyz=mesh["xyz"], moved=mesh["outline_moved_mm"])
        env = dict(os.environ, OMP_NUM_THREADS=str(a.threads), CCX_NPROC_EQUATION_SOLVER=str(a.threads))
        t1 = time.time()
        with open(os.path.join(a.out, "ccx.log"), "w") as log:
            rc = subprocess.call(["ccx", "-i", "liu52"], cwd=a.out, stdout=log, stderr=subprocess.STDOUT, env=env)
        t_ccx = time.time() - t1
        json.dump(dict(pairs=[int(j) for j in pairs], n_disc=int(n_disc), n_pin=int(n_pin), rc=rc, t_ccx=t_ccx,
                       t_mesh=t_mesh, steps=steps), open(os.path.join(a.out, "info.json"), "w"))
    recs = parse_dat(os.path.join(a.out, "liu52.dat"), mesh, state, a)
    # rotation of each record: step-wise ramps (ccx prints the total time: step k runs from k to k + 1)
    samples = []
    cumulative = any(r["time"] > 1.0 + 1e-9 for r in recs)
    step_i, last_t = 0, -1.0
    for r in recs:
        if cumulative:
            step_i = max(0, math.ceil(r["time"] - 1e-9) - 1)
            local = r["time"] - step_i
        else:
            if r["time"] <= last_t + 1e-12:
                step_i += 1
            last_t = local = r["time"]
        if step_i >= len(steps):
            break
        start = 0.0 if step_i == 0 else steps[step_i - 1][0]
        psi = start + (steps[step_i][0] - start) * local
        samples.append(dict(psi=psi, beyond=psi - psi0, torque=r["torque"],
                            pins={str(k): v for k, v in sorted(r["pins"].items())},
                            pmax=r["press"], pen=r["pen"],
                            pmax_face_mean=max([sum(v) / len(v) for v in r["faces"].values()] or [0.0])))
    res = dict(crank_deg=a.crank_deg, bore_mm=a.bore, local_mm=a.local, core_mm=a.core,
               h0_mm=a.h0, d0_mm=a.d0, grow=a.grow, hdisc_mm=a.hdisc, hpin_mm=a.hpin,
               penalty=a.penalty, first_contact_arcsec=psi0, first_contact_pin=first_pin,
               clearances_um={str(j + 1): s["gap"] * 1000 for j, s in state.items()},
               arms_mm={str(j + 1): s["arm"] for j, s in state.items()},
               nodes=len(mesh["xyz"]), disc_elements=n_disc, pin_elements=n_pin,
               contact_pairs=[j + 1 for j in pairs], outline_moved_mm=mesh["outline_moved_mm"],
               ccx_rc=rc, mesh_s=t_mesh, ccx_s=t_ccx, samples=samples)
    # interpolate to the torque
    ts = [s for s in samples if s["torque"] > 0]
    for s1, s2 in zip(ts, ts[1:]):
        if s1["torque"] <= a.torque <= s2["torque"]:
            w = (a.torque - s1["torque"]) / (s2["torque"] - s1["torque"])
            lerp = lambda u, v: u + w * (v - u)
            res["at_torque"] = dict(
                psi=lerp(s1["psi"], s2["psi"]), beyond=lerp(s1["beyond"], s2["beyond"]),
                te_arcsec=-lerp(s1["psi"], s2["psi"]),
                pins={k: lerp(s1["pins"].get(k, 0.0), s2["pins"].get(k, 0.0)) for k in s2["pins"]},
                pmax=lerp(s1["pmax"], s2["pmax"]), pen=lerp(s1["pen"], s2["pen"]),
                pmax_face_mean=lerp(s1["pmax_face_mean"], s2["pmax_face_mean"]),
                bracket=[s1["psi"], s2["psi"]])
    with open(os.path.join(a.out, "result.json"), "w") as fh:
        json.dump(res, fh, indent=1)
    json.dump(res, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
