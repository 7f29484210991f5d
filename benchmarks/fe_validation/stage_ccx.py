#!/usr/bin/python3
"""A plane-strain CalculiX contact model of ONE stage: cases/stage/cycloidal_drive.toml with a
rigid eccentric bearing and the disc an elastic body with its 8 output-pin holes and a 28 mm bore.

The reference for ltca's elastic disc in the stage (issue 48 item 5; docs/validation.md, "The
stage against a CalculiX contact model"). Independent of ltca's code: the profile, the ring-pin
kinematics and the mesh come from liu52_ccx.py (Liu 2021 eq. 1, 14, 15; docs/conventions.md), the
output pins and holes are written here from the deck and docs/conventions.md / docs/stage.md
("Frames and conventions": output pin j at 2 pi j / 8 from +X in the output member's frame, its
hole at the same place in the disc's body frame, the hole centre offset from the pin centre by the
eccentricity at the nominal poses).

Model (crank 0 by default)
  - the disc: Liu's modified profile (as liu52_ccx.py), its centre at e (cos theta, sin theta),
    8 holes of radius 6.32 mm on a 40 mm circle about it, a bore of radius 28 mm;
  - the eccentric bearing, rigid: the bore is filled by a hub of E x 1000 (--hub-stiffness)
    sharing the bore's nodes, whose centre node is held in x and y and nothing else. The bore thus
    moves as a rigid ring (the reference of the disc's pose, as ltca's clamped bore), its
    translation held (a rigid bearing) and its rotation free: one node of a plane solid carries
    no moment, so the bore's reaction moment is zero by construction (no spring, no root search);
    the disc's rotation phi is the bore's, a result (the mean of (r x u) / r^2 over the bore nodes);
  - the ring pins 2-12: elastic annuli of radius 3 mm, rigid cores of radius --core (0.606 mm:
    ltca's pin term, pin_calibration.py) held, as liu52_ccx.py;
  - the output pins 1-5 (those whose approach grows with the output's rotation; 6-8 open by the
    whole clearance): elastic annuli of radius 5 mm whose core (radius --out-core, 1.02 mm: ltca's
    pin-side term of the hole law C (ln(4 r_w / b) - 1/2), pin_calibration.py --radius 5) follows
    the output member's rotation psi about the origin (displacement control: u = psi x r); the
    output torque is the cores' reaction moment about the origin, the pin forces their totals;
  - the rigid mode before contact: the disc turns freely until the ring pins and the output pins
    touch it, so the first step also holds the bore's rotation (one bore node's tangential
    displacement) at phi1 = first ring-pin contact + 0.5 arcsec with psi1 = phi1 + the output
    pins' first contact + 0.5 arcsec (both sides just closed); the second step releases it at the
    same psi (the disc finds its balance), the later steps turn psi;
  - frictionless face-to-face penalty contact, small displacements, CPE6, plane strain, B = 12 mm,
    E = 206,000 MPa, nu = 0.3, as liu52_ccx.py; element sizes: --h0 within --d0 of the ring-pin
    contacts, --hout within --dout of the output-pin contacts, --hhole on the holes' walls,
    growing by --grow per mm to --hdisc (disc), --hpin (ring pins), --hopin (output pins).

Run (one ccx thread; see run_stage.sh):
  /usr/bin/python3 benchmarks/fe_validation/stage_ccx.py --psi 190:210:4 --out /tmp/cx/stage
prints one JSON document (also OUT/result.json): the samples (psi, torque, phi, pin forces,
output-pin forces, bearing force, pressures), and their linear interpolation at --torque.
Nothing is written under the repository.
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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import liu52_ccx as L  # noqa: E402  (the pair, its profile and the ring-pin kinematics)

# the deck's output pins and bore (cases/stage/cycloidal_drive.toml, --set disc.bore_radius_mm=28)
N_OUT, R_W, RW_PIN, R_HOLE = 8, 40.0, 5.0, 6.32
ARCSEC = L.ARCSEC


def out_state(crank):
    """Per output pin: pin centre, hole centre, contact normal (hole -> pin), gap, arm (about the
    origin, of the relative rotation psi - phi), the wall and pin contact points."""
    oc, th = L.pose(crank)
    out = {}
    for j in range(N_OUT):
        a = 2 * math.pi * j / N_OUT
        local = R_W * np.array([math.cos(a), math.sin(a)])
        pc = L.rot(local, th)              # the output member turned as the disc at the nominal poses
        hc = oc + L.rot(local, th)         # the hole in the disc's body frame
        d = pc - hc
        n = d / np.linalg.norm(d)
        gap = R_HOLE - RW_PIN - np.linalg.norm(d)
        # linearised: d(approach) / d(psi - phi) with pin and hole turning about nearly the same
        # centre: n . (perp(pc)) (the pin moving along n closes the gap)
        arm = n[0] * (-pc[1]) + n[1] * pc[0]
        out[j] = dict(pin=pc, hole=hc, normal=n, gap=gap, arm=arm,
                      wall_point=hc + R_HOLE * n, pin_point=pc + RW_PIN * n)
    return out


def circle(geo, c, r):
    cp = geo.addPoint(c[0], c[1], 0.0)
    ps = [geo.addPoint(c[0] + r * math.cos(t), c[1] + r * math.sin(t), 0.0) for t in (0, 0.5 * math.pi, math.pi, 1.5 * math.pi)]
    return [geo.addCircleArc(ps[i], cp, ps[(i + 1) % 4]) for i in range(4)]


def build_mesh(a, state, ostate, refined_pins, opins):
    import gmsh
    oc, th = L.pose(a.crank)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.model.add("stage")
    geo = gmsh.model.geo
    npts = a.spline_points
    us = np.linspace(-L.HALF, L.HALF, npts + 1)
    xs, _ = L.profile(us)
    first = prev_end = None
    curves = []
    for k in range(L.ZC):
        pts = oc + L.rot(L.rot(xs, 2 * L.HALF * k), th)
        tags = []
        for i in range(npts + 1):
            if i == 0 and prev_end is not None:
                tags.append(prev_end)
                continue
            if k == L.ZC - 1 and i == npts:
                tags.append(first)
                continue
            tags.append(geo.addPoint(pts[i, 0], pts[i, 1], 0.0))
        if first is None:
            first = tags[0]
        prev_end = tags[-1]
        curves.append(geo.addSpline(tags))
    outline_loop = geo.addCurveLoop(curves)
    bore_arcs = circle(geo, oc, a.bore)
    hole_arcs = {j: circle(geo, ostate[j]["hole"], R_HOLE) for j in range(N_OUT)}
    disc_surf = geo.addPlaneSurface([outline_loop, geo.addCurveLoop(bore_arcs)] +
                                    [geo.addCurveLoop(hole_arcs[j]) for j in range(N_OUT)])
    hub_surf = geo.addPlaneSurface([geo.addCurveLoop(bore_arcs)])
    hub_centre = geo.addPoint(oc[0], oc[1], 0.0)
    pin_surf, pin_outer, pin_core = {}, {}, {}
    for j in state:
        pc = L.pin_centre(j)
        pin_outer[j], pin_core[j] = circle(geo, pc, L.RRP), circle(geo, pc, a.core)
        pin_surf[j] = geo.addPlaneSurface([geo.addCurveLoop(pin_outer[j]), geo.addCurveLoop(pin_core[j])])
    op_surf, op_outer, op_core = {}, {}, {}
    for j in opins:
        pc = ostate[j]["pin"]
        op_outer[j], op_core[j] = circle(geo, pc, RW_PIN), circle(geo, pc, a.out_core)
        op_surf[j] = geo.addPlaneSurface([geo.addCurveLoop(op_outer[j]), geo.addCurveLoop(op_core[j])])
    fr = []
    for j in refined_pins:
        for p in (state[j]["point"], state[j]["pin_point"]):
            fr.append(geo.addPoint(p[0], p[1], 0.0))
    fx = []  # --fine-pins: a finer size at these ring pins' contacts
    for j in a.fine_pins:
        for p in (state[j]["point"], state[j]["pin_point"]):
            fx.append(geo.addPoint(p[0], p[1], 0.0))
    fo = []
    for j in opins:
        for p in (ostate[j]["wall_point"], ostate[j]["pin_point"]):
            fo.append(geo.addPoint(p[0], p[1], 0.0))
    geo.synchronize()
    gmsh.model.mesh.embed(0, [hub_centre], 2, hub_surf)
    f = gmsh.model.mesh.field

    def dist_pts(tags):
        d = f.add("Distance")
        f.setNumbers(d, "PointsList", tags)
        return d

    def dist_curves(tags):
        d = f.add("Distance")
        f.setNumbers(d, "CurvesList", tags)
        try:  # gmsh 4.8 calls it NumPointsPerCurve, later versions Sampling
            f.setNumber(d, "NumPointsPerCurve", 200)
        except Exception:
            f.setNumber(d, "Sampling", 200)
        return d

    def threshold(din, hmin, hmax, dmin):
        t = f.add("Threshold")
        f.setNumber(t, "InField", din)
        f.setNumber(t, "SizeMin", hmin)
        f.setNumber(t, "SizeMax", hmax)
        f.setNumber(t, "DistMin", dmin)
        f.setNumber(t, "DistMax", dmin + max(hmax - hmin, 1e-9) / a.grow)
        return t

    def restrict(field, surfs, cs):
        r = f.add("Restrict")
        f.setNumber(r, "InField", field)
        f.setNumbers(r, "SurfacesList", surfs)
        f.setNumbers(r, "CurvesList", cs)
        return r

    dr, do = dist_pts(fr), dist_pts(fo)
    dh = dist_curves([c for j in range(N_OUT) for c in hole_arcs[j]])
    all_hole_arcs = [c for j in range(N_OUT) for c in hole_arcs[j]]
    pin_cs = [c for j in state for c in pin_outer[j] + pin_core[j]]
    disc_cs = curves + bore_arcs + all_hole_arcs
    fields = [
        restrict(threshold(dr, a.h0, a.hdisc, a.d0), [disc_surf], disc_cs),
        restrict(threshold(do, a.hout, a.hdisc, a.dout), [disc_surf], disc_cs),
        restrict(threshold(dh, a.hhole, a.hdisc, 0.0), [disc_surf], disc_cs),
        restrict(threshold(dr, a.h0, a.hpin, a.d0), list(pin_surf.values()),
                 [c for j in state for c in pin_outer[j] + pin_core[j]]),
        restrict(threshold(do, a.hout, a.hopin, a.dout), list(op_surf.values()),
                 [c for j in opins for c in op_outer[j] + op_core[j]]),
    ]
    if fx:
        dx = dist_pts(fx)
        fields += [restrict(threshold(dx, a.h0_fine, a.hdisc, a.d0), [disc_surf], curves + bore_arcs + all_hole_arcs),
                   restrict(threshold(dx, a.h0_fine, a.hpin, a.d0), list(pin_surf.values()), pin_cs)]
    hub_size = f.add("MathEval")
    f.setString(hub_size, "F", "%g" % a.hhub)
    fields.append(restrict(hub_size, [hub_surf], []))
    mn = f.add("Min")
    f.setNumbers(mn, "FieldsList", fields)
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

    hc_nodes, _, _ = gmsh.model.mesh.getNodes(0, hub_centre)
    mesh = dict(xyz=xyz.copy(), disc=tris(disc_surf), hub=tris(hub_surf),
                pins={j: tris(pin_surf[j]) for j in state}, opins={j: tris(op_surf[j]) for j in opins},
                outline=curve_nodes(curves), bore=curve_nodes(bore_arcs),
                holes={j: curve_nodes(hole_arcs[j]) for j in range(N_OUT)},
                pin_outer={j: curve_nodes(pin_outer[j]) for j in state},
                pin_core={j: curve_nodes(pin_core[j]) for j in state},
                op_outer={j: curve_nodes(op_outer[j]) for j in opins},
                op_core={j: curve_nodes(op_core[j]) for j in opins},
                hub_centre=idx[int(hc_nodes[0])])
    gmsh.finalize()
    x = mesh["xyz"]
    ob = mesh["outline"]
    pb = L.rot(x[ob] - oc, -th)
    xb, _, _, _ = L.project_to_profile(pb)
    mesh["outline_moved_mm"] = float(np.max(np.linalg.norm(xb - pb, axis=1)))
    x[ob] = oc + L.rot(xb, th)

    def onto_circle(nodes, c, r):
        d = x[nodes] - c
        x[nodes] = c + r * d / np.linalg.norm(d, axis=1, keepdims=True)

    onto_circle(mesh["bore"], oc, a.bore)
    for j in range(N_OUT):
        onto_circle(mesh["holes"][j], ostate[j]["hole"], R_HOLE)
    for j in state:
        onto_circle(mesh["pin_outer"][j], L.pin_centre(j), L.RRP)
        onto_circle(mesh["pin_core"][j], L.pin_centre(j), a.core)
    for j in opins:
        onto_circle(mesh["op_outer"][j], ostate[j]["pin"], RW_PIN)
        onto_circle(mesh["op_core"][j], ostate[j]["pin"], a.out_core)
    return mesh


def write_deck(path, a, mesh, state, ostate, opins, phi1, psi1, psi_steps):
    x = mesh["xyz"]
    oc, _ = L.pose(a.crank)
    lines = ["** cycloidal_drive.toml stage, rigid bearing, elastic disc; written by benchmarks/fe_validation/stage_ccx.py",
             "*NODE, NSET=NALL"]
    lines += ["%d,%.12f,%.12f" % (i + 1, p[0], p[1]) for i, p in enumerate(x)]
    eid = 1
    groups = []
    disc = L.orient(mesh["disc"], x)
    groups.append(("DISC", disc, eid)); disc_first = eid; eid += len(disc)
    hub = L.orient(mesh["hub"], x)
    groups.append(("HUB", hub, eid)); eid += len(hub)
    pin_el, pin_first = {}, {}
    for j in state:
        pin_el[j] = L.orient(mesh["pins"][j], x)
        groups.append(("PIN%d" % (j + 1), pin_el[j], eid)); pin_first[j] = eid; eid += len(pin_el[j])
    op_el, op_first = {}, {}
    for j in opins:
        op_el[j] = L.orient(mesh["opins"][j], x)
        groups.append(("OPIN%d" % (j + 1), op_el[j], eid)); op_first[j] = eid; eid += len(op_el[j])
    for name, el, first in groups:
        lines.append("*ELEMENT, TYPE=CPE6, ELSET=%s" % name)
        lines += ["%d,%s" % (first + i, ",".join(str(int(n) + 1) for n in e)) for i, e in enumerate(el)]
    lines.append("*NSET, NSET=BORE")
    lines += [str(int(n) + 1) for n in mesh["bore"]]
    lines += ["*NSET, NSET=HUBC", str(mesh["hub_centre"] + 1)]
    # the bore node nearest to the top: its x holds the rotation in the first step
    top = mesh["bore"][np.argmin(np.linalg.norm(x[mesh["bore"]] - (oc + np.array([0.0, a.bore])), axis=1))]
    lines += ["*NSET, NSET=BTOP", str(int(top) + 1)]
    for j in state:
        lines.append("*NSET, NSET=CORE%d" % (j + 1))
        lines += [str(int(n) + 1) for n in mesh["pin_core"][j]]
    for j in opins:
        lines.append("*NSET, NSET=OCORE%d" % (j + 1))
        lines += [str(int(n) + 1) for n in mesh["op_core"][j]]
    lines.append("*NSET, NSET=OCORES")
    lines += ["OCORE%d" % (j + 1) for j in opins]
    pairs, slave_elems = [], {}
    for j in state:
        c = state[j]["point"]
        sd = L.faces_on(disc, mesh["outline"], x, c, a.surf_radius, disc_first)
        sp = L.faces_on(pin_el[j], mesh["pin_outer"][j], x, c, a.surf_radius, pin_first[j])
        if not sd or not sp:
            continue
        name = "P%d" % (j + 1)
        lines.append("*SURFACE, NAME=SD%s, TYPE=ELEMENT" % name)
        lines += ["%d,S%d" % fc for fc in sd]
        lines.append("*SURFACE, NAME=SM%s, TYPE=ELEMENT" % name)
        lines += ["%d,S%d" % fc for fc in sp]
        pairs.append(name)
        slave_elems.update({fc[0]: name for fc in sd})
    for j in opins:
        c = ostate[j]["wall_point"]
        sd = L.faces_on(disc, mesh["holes"][j], x, c, a.out_surf_radius, disc_first)
        sp = L.faces_on(op_el[j], mesh["op_outer"][j], x, ostate[j]["pin_point"], a.out_surf_radius, op_first[j])
        if not sd or not sp:
            continue
        name = "O%d" % (j + 1)
        lines.append("*SURFACE, NAME=SD%s, TYPE=ELEMENT" % name)
        lines += ["%d,S%d" % fc for fc in sd]
        lines.append("*SURFACE, NAME=SM%s, TYPE=ELEMENT" % name)
        lines += ["%d,S%d" % fc for fc in sp]
        pairs.append(name)
        slave_elems.update({fc[0]: name for fc in sd})
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "%g,%g" % (L.E_MOD, L.NU)]
    lines += ["*MATERIAL, NAME=HUBM", "*ELASTIC", "%g,%g" % (L.E_MOD * a.hub_stiffness, L.NU)]
    for name, _, _ in groups:
        lines += ["*SOLID SECTION, ELSET=%s, MATERIAL=%s" % (name, "HUBM" if name == "HUB" else "STEEL"), "%g" % L.B]
    lines += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", "%g" % a.penalty]
    for name in pairs:  # slave: the disc (flank or hole wall); master: the pin
        lines += ["*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SD%s,SM%s" % (name, name)]

    def core_bc(psi_arcsec):
        ps = psi_arcsec * ARCSEC
        out = []
        for j in opins:
            for n in mesh["op_core"][j]:
                r = x[n]
                out.append("%d,1,1,%.12e" % (n + 1, -ps * r[1]))
                out.append("%d,2,2,%.12e" % (n + 1, ps * r[0]))
        return out

    def prints():
        out = ["*NODE PRINT, NSET=BORE", "U", "*NODE PRINT, NSET=HUBC", "RF", "*NODE PRINT, NSET=OCORES", "U,RF"]
        for j in state:
            out += ["*NODE PRINT, NSET=CORE%d, TOTALS=ONLY" % (j + 1), "RF"]
        for j in opins:
            out += ["*NODE PRINT, NSET=OCORE%d, TOTALS=ONLY" % (j + 1), "RF"]
        return out + ["*CONTACT PRINT", "CSTR,CDIS"]

    fixed = ["HUBC,1,2,0."] + ["CORE%d,1,2,0." % (j + 1) for j in state]
    # step 1: the disc's rotation held at phi1 (one bore node), the output at psi1: both sides close
    lines += ["*STEP, INC=1000", "*STATIC", "0.5,1.,1e-5,0.5", "*BOUNDARY"] + fixed
    lines.append("BTOP,1,1,%.12e" % (-phi1 * ARCSEC * a.bore))
    lines += core_bc(psi1) + prints() + ["*END STEP"]
    # step 2: the rotation released (the bore a free rigid ring about its held centre)
    lines += ["*STEP, INC=1000", "*STATIC", "0.5,1.,1e-5,0.5", "*BOUNDARY, OP=NEW"] + fixed
    lines += core_bc(psi1) + prints() + ["*END STEP"]
    for psi, ninc in psi_steps:
        lines.append("*STEP, INC=1000")
        if ninc:
            lines += ["*STATIC, DIRECT", "%g,1." % (1.0 / ninc)]
        else:
            lines += ["*STATIC", "%g,1.,1e-5,%g" % (a.first_inc, max(a.first_inc, 0.25))]
        lines += ["*BOUNDARY"] + core_bc(psi) + prints() + ["*END STEP"]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    return pairs, slave_elems, dict(disc=len(disc), hub=len(hub), pins=sum(len(v) for v in pin_el.values()),
                                    opins=sum(len(v) for v in op_el.values()))


def parse_dat(path, mesh, a, slave_elems):
    """One record per printed increment: psi and phi (from the nodes' displacements), the output
    torque (the output cores' reaction moment about the origin), the pin and output-pin forces,
    the hub's (bearing) force, the largest contact pressure per pair (face means and integration
    points) and the largest overclosure."""
    oc, _ = L.pose(a.crank)
    x = mesh["xyz"]
    txt = open(path).read().split("\n")
    recs = []
    cur = None
    i = 0

    def block(i):
        rows = []
        while i < len(txt) and txt[i].strip():
            rows.append(txt[i].split())
            i += 1
        return rows, i

    while i < len(txt):
        line = txt[i]
        m = re.search(r"displacements \(vx,vy,vz\) for set BORE and time\s+(\S+)", line)
        if m:
            cur = dict(time=float(m.group(1)), pins={}, opins={}, pmax={}, pmax_ip={}, pen=0.0, faces={})
            recs.append(cur)
            rows, i = block(i + 2)
            ph = []
            for f in rows:
                n = int(f[0]) - 1
                r = x[n] - oc
                ph.append((r[0] * L.ffloat(f[2]) - r[1] * L.ffloat(f[1])) / (r @ r))
            cur["phi"] = float(np.mean(ph)) / ARCSEC
            cur["phi_spread"] = float(np.ptp(ph)) / ARCSEC
            continue
        m = re.search(r"forces \(fx,fy,fz\) for set HUBC and time", line)
        if m and cur is not None:
            f = txt[i + 2].split()
            cur["bearing"] = math.hypot(L.ffloat(f[1]), L.ffloat(f[2]))
            i += 3
            continue
        m = re.search(r"displacements \(vx,vy,vz\) for set OCORES and time", line)
        if m and cur is not None:
            rows, i = block(i + 2)
            ps = []
            for f in rows:
                r = x[int(f[0]) - 1]
                ps.append((r[0] * L.ffloat(f[2]) - r[1] * L.ffloat(f[1])) / (r @ r))
            cur["psi"] = float(np.mean(ps)) / ARCSEC
            continue
        m = re.search(r"forces \(fx,fy,fz\) for set OCORES and time", line)
        if m and cur is not None:
            rows, i = block(i + 2)
            tq = 0.0
            for f in rows:
                r = x[int(f[0]) - 1]
                tq += r[0] * L.ffloat(f[2]) - r[1] * L.ffloat(f[1])
            cur["torque"] = tq / 1000.0
            continue
        m = re.search(r"total force \(fx,fy,fz\) for set (O?)CORE(\d+) and time", line)
        if m and cur is not None:
            f = txt[i + 2].split()
            key = "opins" if m.group(1) else "pins"
            cur[key][int(m.group(2))] = math.hypot(L.ffloat(f[0]), L.ffloat(f[1]))
            i += 3
            continue
        if "contact stress" in line and cur is not None:
            rows, i = block(i + 2)
            for f in rows:
                name = slave_elems.get(int(f[0]), "?")
                p = L.ffloat(f[-3])
                cur["pmax_ip"][name] = max(cur["pmax_ip"].get(name, 0.0), p)
                cur["faces"].setdefault((name, f[0], f[1]), []).append(p)
            for (name, _, _), v in cur["faces"].items():
                cur["pmax"][name] = max(cur["pmax"].get(name, 0.0), sum(v) / len(v))
            continue
        if "relative contact displacement" in line and cur is not None:
            rows, i = block(i + 2)
            for f in rows:
                cur["pen"] = max(cur["pen"], -L.ffloat(f[-3]))
            continue
        i += 1
    for r in recs:
        r.pop("faces")
    return recs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--crank-deg", type=float, default=0.0)
    ap.add_argument("--bore", type=float, default=28.0, help="bore radius, mm (the deck's --set disc.bore_radius_mm=28)")
    ap.add_argument("--torque", type=float, default=206.0, help="N*m")
    ap.add_argument("--pins", default="2-12", help="ring pins modelled (printed numbers)")
    ap.add_argument("--refine", default="3,4,5,6,7,8,9,10", help="ring pins whose contacts are refined")
    ap.add_argument("--opins", default="1-5", help="output pins modelled (printed numbers)")
    ap.add_argument("--core", type=float, default=0.606, help="ring pin's rigid core radius, mm (pin_calibration.py)")
    ap.add_argument("--out-core", type=float, default=1.02,
                    help="output pin's rigid core radius, mm (1.010 / 1.025: ltca's pin term at b = 0.1 / 0.325 mm, pin_calibration.py --radius 5)")
    ap.add_argument("--hub-stiffness", type=float, default=1000.0, help="the hub's E over the disc's")
    ap.add_argument("--h0", type=float, default=0.02, help="element size at the ring-pin contacts, mm")
    ap.add_argument("--d0", type=float, default=0.12)
    ap.add_argument("--fine-pins", default="", help="ring pins whose contacts get --h0-fine (a pressure check)")
    ap.add_argument("--h0-fine", type=float, default=0.005)
    ap.add_argument("--hout", type=float, default=0.04, help="element size at the output-pin contacts, mm")
    ap.add_argument("--dout", type=float, default=0.6, help="radius of the uniform hout zone, mm")
    ap.add_argument("--hhole", type=float, default=0.6, help="element size on the holes' walls, mm")
    ap.add_argument("--grow", type=float, default=0.3, help="size growth per mm of distance")
    ap.add_argument("--hdisc", type=float, default=2.0)
    ap.add_argument("--hpin", type=float, default=0.4)
    ap.add_argument("--hopin", type=float, default=0.8)
    ap.add_argument("--hhub", type=float, default=4.0)
    ap.add_argument("--spline-points", type=int, default=400)
    ap.add_argument("--algorithm", type=int, default=6)
    ap.add_argument("--penalty", type=float, default=1e9, help="contact slope, MPa/mm")
    ap.add_argument("--surf-radius", type=float, default=0.5, help="ring-pin contact surfaces within this of the contact point, mm")
    ap.add_argument("--out-surf-radius", type=float, default=1.5, help="output-pin contact surfaces within this of the contact point, mm")
    ap.add_argument("--psi", default="190:210:4", help="output rotations, arcsec from the nominal pose: 'a:b:n' (ramp to a, then n equal increments to b)")
    ap.add_argument("--first-inc", type=float, default=0.25)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--deck-only", action="store_true", help="mesh and write OUT/stage.inp, no solve")
    ap.add_argument("--reparse", action="store_true", help="read OUT's results again (mesh from OUT/mesh.npz)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    a.crank = math.radians(a.crank_deg)
    lo, hi = [int(v) for v in a.pins.split("-")]
    pins = list(range(lo - 1, hi))
    refine = [int(v) - 1 for v in a.refine.split(",")]
    a.fine_pins = [int(v) - 1 for v in a.fine_pins.split(",")] if a.fine_pins else []
    olo, ohi = [int(v) for v in a.opins.split("-")]
    opins = list(range(olo - 1, ohi))
    os.makedirs(a.out, exist_ok=True)
    t0 = time.time()
    state = L.mesh_state(a.crank, pins)
    ostate = out_state(a.crank)
    loaded = {j: s for j, s in state.items() if s["arm"] > 0}
    phi0 = min(s["gap"] / s["arm"] for s in loaded.values()) / ARCSEC
    oloaded = {j: s for j, s in ostate.items() if s["arm"] > 1e-9}
    rel0 = min(s["gap"] / s["arm"] for s in oloaded.values()) / ARCSEC
    phi1 = phi0 + 0.5
    psi1 = phi1 + rel0 + 0.5
    p1, p2, n = a.psi.split(":")
    steps = [(float(p1), 0), (float(p2), int(n))]
    if a.reparse:
        z = np.load(os.path.join(a.out, "mesh.npz"), allow_pickle=True)
        mesh = dict(xyz=z["xyz"])
        info = json.load(open(os.path.join(a.out, "info.json")))
        slave = {int(k): v for k, v in info["slave"].items()}
    else:
        mesh = build_mesh(a, state, ostate, refine, opins)
        t_mesh = time.time() - t0
        pairs, slave, counts = write_deck(os.path.join(a.out, "stage.inp"), a, mesh, state, ostate, opins, phi1, psi1, steps)
        np.savez(os.path.join(a.out, "mesh.npz"), xyz=mesh["xyz"])
        if a.deck_only:
            print(json.dumps(dict(nodes=len(mesh["xyz"]), counts=counts, pairs=pairs, t_mesh=t_mesh, phi1=phi1, psi1=psi1,
                                  moved=mesh["outline_moved_mm"])))
            return
        env = dict(os.environ, OMP_NUM_THREADS=str(a.threads), CCX_NPROC_EQUATION_SOLVER=str(a.threads))
        t1 = time.time()
        with open(os.path.join(a.out, "ccx.log"), "w") as log:
            rc = subprocess.call(["ccx", "-i", "stage"], cwd=a.out, stdout=log, stderr=subprocess.STDOUT, env=env)
        t_ccx = time.time() - t1
        info = dict(pairs=pairs, slave={str(k): v for k, v in slave.items()}, counts=counts, rc=rc, t_ccx=t_ccx,
                    t_mesh=t_mesh, nodes=len(mesh["xyz"]), outline_moved_mm=mesh["outline_moved_mm"])
        json.dump(info, open(os.path.join(a.out, "info.json"), "w"))
    recs = parse_dat(os.path.join(a.out, "stage.dat"), mesh, a, slave)
    res = dict(crank_deg=a.crank_deg, fine_pins=[j + 1 for j in a.fine_pins], h0_fine_mm=a.h0_fine, bore_mm=a.bore, core_mm=a.core, out_core_mm=a.out_core, h0_mm=a.h0, d0_mm=a.d0,
               hout_mm=a.hout, dout_mm=a.dout, hhole_mm=a.hhole, grow=a.grow, hdisc_mm=a.hdisc, hpin_mm=a.hpin,
               hopin_mm=a.hopin, hub_stiffness=a.hub_stiffness, penalty=a.penalty,
               first_ring_contact_arcsec=phi0, first_output_contact_rel_arcsec=rel0, phi1=phi1, psi1=psi1,
               clearances_um={str(j + 1): s["gap"] * 1000 for j, s in state.items()},
               arms_mm={str(j + 1): s["arm"] for j, s in state.items()},
               output_gaps_um={str(j + 1): s["gap"] * 1000 for j, s in ostate.items()},
               output_arms_mm={str(j + 1): s["arm"] for j, s in ostate.items()},
               nodes=info["nodes"], elements=info["counts"], contact_pairs=info["pairs"],
               outline_moved_mm=info["outline_moved_mm"], ccx_rc=info["rc"], mesh_s=info["t_mesh"], ccx_s=info["t_ccx"],
               samples=recs)
    # interpolate to the torque along the records after the release (step 2 on): psi rises
    ts = [r for r in recs if "torque" in r and r["torque"] > 0]
    ts.sort(key=lambda r: r["psi"])
    for s1, s2 in zip(ts, ts[1:]):
        if s1["torque"] <= a.torque <= s2["torque"] and s2["psi"] > s1["psi"] + 1e-6:
            w = (a.torque - s1["torque"]) / (s2["torque"] - s1["torque"])
            lerp = lambda u, v: u + w * (v - u)
            keys = lambda d1, d2: sorted(set(d1) | set(d2), key=lambda k: (len(str(k)), str(k)))
            res["at_torque"] = dict(
                psi=lerp(s1["psi"], s2["psi"]), te_arcsec=-lerp(s1["psi"], s2["psi"]), phi=lerp(s1["phi"], s2["phi"]),
                pins={str(k): lerp(s1["pins"].get(k, 0.0), s2["pins"].get(k, 0.0)) for k in keys(s1["pins"], s2["pins"])},
                opins={str(k): lerp(s1["opins"].get(k, 0.0), s2["opins"].get(k, 0.0)) for k in keys(s1["opins"], s2["opins"])},
                bearing=lerp(s1["bearing"], s2["bearing"]),
                pmax={k: lerp(s1["pmax"].get(k, 0.0), s2["pmax"].get(k, 0.0)) for k in keys(s1["pmax"], s2["pmax"])},
                pmax_ip={k: lerp(s1["pmax_ip"].get(k, 0.0), s2["pmax_ip"].get(k, 0.0)) for k in keys(s1["pmax_ip"], s2["pmax_ip"])},
                pen=lerp(s1["pen"], s2["pen"]), bracket=[s1["psi"], s2["psi"]])
            break
    with open(os.path.join(a.out, "result.json"), "w") as fh:
        json.dump(res, fh, indent=1)
    json.dump(res, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
