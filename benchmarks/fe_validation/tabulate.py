#!/usr/bin/python3
"""Tables of docs/validation.md's section "The elastic disc against a CalculiX contact model".

Reads the result.json of liu52_ccx.py runs (given as directories) and prints, for each, the
rotation beyond first contact, TE, pin forces, largest pressure and penetration beside ltca's
rigid disc at the same crank (ltca solve cases/liu2021_sec52_base.toml --set
contact.rho_convention=signed, one position; ltca mesh for the clearances and arms).

Run: /usr/bin/python3 benchmarks/fe_validation/tabulate.py --ltca build/release/ltca DIR...
"""
import argparse
import json
import subprocess

ARCSEC_PER_RAD = 180.0 / 3.141592653589793 * 3600.0


def ltca_rigid(ltca, crank):
    deck = "cases/liu2021_sec52_base.toml"
    sets = ["--set", "contact.rho_convention=signed"]
    solve = json.loads(subprocess.run(
        [ltca, "solve", deck, *sets, "--set", "sweep.positions=1", "--set", "sweep.crank_start_deg=%g" % crank,
         "--set", "sweep.crank_end_deg=%g" % crank, "--json", "-"], capture_output=True, text=True).stdout)
    mesh = json.loads(subprocess.run([ltca, "mesh", deck, *sets, "--crank-deg", "%g" % crank, "--json", "-"],
                                     capture_output=True, text=True).stdout)
    p = solve["positions"][0]
    return p, mesh


def first_contact(mesh):
    rows = mesh.get("pins") or mesh.get("rows") or mesh
    best = None
    for r in rows:
        c = r.get("clearance_um", r.get("c_um"))
        arm = r.get("arm_mm", r.get("L_mm"))
        if arm is not None and arm > 0:
            v = c * 1e-3 / arm * ARCSEC_PER_RAD
            best = v if best is None or v < best else best
    return best


def quadratic_at_torque(r, torque):
    """psi and pin forces at the torque from a quadratic through the three samples nearest to it
    (liu52_ccx.py's at_torque is the linear interpolation between the two that bracket it)."""
    import numpy as np
    ss = [s for s in r["samples"] if s["torque"] > 0]
    uniq = []
    for s in ss:  # ccx repeats a sample after an increment of 1e-6
        if not uniq or abs(s["psi"] - uniq[-1]["psi"]) > 1e-3:
            uniq.append(s)
    uniq.sort(key=lambda s: abs(s["torque"] - torque))
    near = sorted(uniq[:3], key=lambda s: s["psi"])
    if len(near) < 3:
        return None
    tq = np.array([s["torque"] for s in near])
    ps = np.array([s["beyond"] for s in near])
    beyond = float(np.polyval(np.polyfit(tq, ps, 2), torque))
    pins = {}
    lin = r["at_torque"]["pins"]
    for k in near[-1]["pins"]:
        f = np.array([s["pins"].get(k, 0.0) for s in near])
        # a pin that is open at one of the three has a kink between them: the linear value
        pins[k] = float(np.polyval(np.polyfit(ps, f, 2), beyond)) if f.min() > 0 else lin.get(k, 0.0)
    pm = np.array([s["pmax_face_mean"] for s in near])
    return dict(beyond=beyond, pins=pins, pmax_face_mean=float(np.polyval(np.polyfit(ps, pm, 2), beyond)),
                samples=[round(s["beyond"], 3) for s in near])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ltca", default="build/release/ltca")
    ap.add_argument("dirs", nargs="+")
    a = ap.parse_args()
    for d in a.dirs:
        r = json.load(open(d + "/result.json"))
        t = r.get("at_torque")
        p, mesh = ltca_rigid(a.ltca, r["crank_deg"])
        fc = first_contact(mesh)
        print("### %s: crank %g deg, bore %g mm%s" % (d, r["crank_deg"], r["bore_mm"],
                                                       ", local %g mm" % r["local_mm"] if r["local_mm"] else ""))
        print("mesh: %d nodes, %d + %d CPE6 (disc + pins), h0 %g um, ccx %.0f s, mesh %.1f s, penalty %g MPa/mm" % (
            r["nodes"], r["disc_elements"], r["pin_elements"], r["h0_mm"] * 1e3, r["ccx_s"], r["mesh_s"], r["penalty"]))
        if not t:
            print("no bracket of the torque")
            continue
        q = quadratic_at_torque(r, 206.0)
        print("linear interpolation: beyond %.3f, pins %s, pmax (integration points) %.1f, (face means) %.1f" % (
            t["beyond"], {k: round(v, 1) for k, v in t["pins"].items() if v > 0.5}, t["pmax"], t["pmax_face_mean"]))
        if q:
            print("quadratic through %s: beyond %.3f, pins %s, pmax (face means) %.1f" % (
                q["samples"], q["beyond"], {k: round(v, 1) for k, v in q["pins"].items() if v > 0.5}, q["pmax_face_mean"]))
            t = dict(t, beyond=q["beyond"], te_arcsec=-(q["beyond"] + r["first_contact_arcsec"]), pins=q["pins"])
        print("| | rotation beyond first contact, arcsec | TE, arcsec | largest pressure, MPa |")
        print("|---|---|---|---|")
        print("| FE | %.2f | %.2f | %.0f |" % (t["beyond"], t["te_arcsec"], t["pmax_face_mean"]))
        print("| ltca rigid | %.2f | %.2f | %.0f |" % (-p["te_arcsec"] - fc, p["te_arcsec"], max(p["contact_stress_mpa"])))
        pins = sorted(set(int(k) for k, v in t["pins"].items() if v > 0.5) |
                      set(i + 1 for i, f in enumerate(p["pin_force_n"]) if f > 0.5))
        print("| pin | " + " | ".join(str(j) for j in pins) + " |")
        print("|---|" + "---|" * len(pins))
        print("| FE, N | " + " | ".join("%.1f" % t["pins"].get(str(j), 0.0) for j in pins) + " |")
        print("| ltca rigid, N | " + " | ".join("%.1f" % p["pin_force_n"][j - 1] for j in pins) + " |")
        print("first contact: FE mesh %.3f arcsec (pin %d), ltca %.3f; penetration %.4f um" % (
            r["first_contact_arcsec"], r["first_contact_pin"], fc, t["pen"] * 1e3))
        print()


if __name__ == "__main__":
    main()
