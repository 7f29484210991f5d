#!/usr/bin/python3
"""Tables of docs/validation.md's section "The stage against a CalculiX contact model".

Reads the result.json of stage_ccx.py runs (directories, coarse to fine) and prints them beside
ltca's stage at crank 0, 206 N*m: cases/stage/cycloidal_drive.toml with its [bearing] replaced by
kind = "rigid" (the disc's centre held; the roller keys belong to kind = "rollers", so the deck is
rewritten to a temporary file, nothing under the repository), one position, bisection, with
--set disc.body=elastic --set disc.bore_radius_mm=28 and without (the rigid body), under the
deck's rho_convention (absolute) and signed, linearised and exact kinematics.

Run: /usr/bin/python3 benchmarks/fe_validation/tabulate_stage.py --ltca build/release/ltca DIR...
"""
import argparse
import json
import os
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = os.path.join(HERE, "..", "..", "cases", "stage", "cycloidal_drive.toml")


def rigid_bearing_deck(tmp):
    s = open(DECK).read()
    a, b = s.index("[bearing]"), s.index("[contact]")
    s = s[:a] + '[bearing]\nkind = "rigid"\n\n' + s[b:]
    path = os.path.join(tmp, "cycloidal_drive_rigid_bearing.toml")
    open(path, "w").write(s)
    return path


def ltca_run(ltca, deck, body, conv, kin):
    sets = ["--set", "sweep.positions=1", "--set", "sweep.crank_start_deg=0", "--set", "sweep.crank_end_deg=0",
            "--set", "contact.rho_convention=" + conv, "--set", "solver.kinematics=" + kin]
    if body == "elastic":
        sets += ["--set", "disc.body=elastic", "--set", "disc.bore_radius_mm=28"]
    out = subprocess.run([ltca, "solve", deck, *sets, "--json", "-"], capture_output=True, text=True)
    p = json.loads(out.stdout)["positions"][0]
    s = p["stage"]["discs"][0]
    return dict(te=p["te_arcsec"], phi=s["rotation_arcsec"], status=p["status"],
                pins={i + 1: f for i, f in enumerate(p["pin_force_n"])},
                pmax=max(p["contact_stress_mpa"]), contacts=p["contacts"],
                opins={i + 1: f for i, f in enumerate(s["output_pin_force_n"])}, bearing=s["bearing_load_n"][0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ltca", default="build/release/ltca")
    ap.add_argument("dirs", nargs="+")
    a = ap.parse_args()
    fe = []
    for d in a.dirs:
        r = json.load(open(os.path.join(d, "result.json")))
        t = r.get("at_torque")
        print("### %s: %d nodes, CPE6 %s, h0 %g um (ring pins), hout %g um (output pins), hhole %g, hdisc %g mm; "
              "ccx %.0f s, mesh %.1f s; first ring contact %.3f arcsec, output pins' first contact %.3f arcsec beyond the disc"
              % (d, r["nodes"], r["elements"], r["h0_mm"] * 1e3, r["hout_mm"] * 1e3, r["hhole_mm"], r["hdisc_mm"],
                 r["ccx_s"], r["mesh_s"], r["first_ring_contact_arcsec"], r["first_output_contact_rel_arcsec"]))
        if not t:
            print("no bracket of the torque: samples (psi, torque) %s" % [
                (round(s.get("psi", 0), 2), round(s.get("torque", 0), 2)) for s in r["samples"]])
            continue
        print("bracket psi %s arcsec, penetration %.4f um" % ([round(v, 3) for v in t["bracket"]], t["pen"] * 1e3))
        fe.append((d, r, t))
    print()
    print("| mesh | nodes | CPE6 disc + hub + ring pins + output pins | TE, arcsec | disc rotation | ring pins 3 .. 9, N | output pins 2, 3, 4, N | "
          "largest pressure (face means): flank / hole wall, MPa | penetration, um | ccx wall, s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for d, r, t in fe:
        e = r["elements"]
        print("| h0 %g um, hout %g um, hhole %g mm, hdisc %g mm | %d | %d + %d + %d + %d | %.3f | %.3f | %s | %s | %.0f (pin %s) / %.0f | %.4f | %.0f |" % (
            r["h0_mm"] * 1e3, r["hout_mm"] * 1e3, r["hhole_mm"], r["hdisc_mm"], r["nodes"], e["disc"], e["hub"], e["pins"], e["opins"],
            t["te_arcsec"], t["phi"], ", ".join("%.1f" % t["pins"].get(str(j), 0.0) for j in range(3, 10)),
            ", ".join("%.1f" % t["opins"].get(str(j), 0.0) for j in (2, 3, 4)),
            max(v for k, v in t["pmax"].items() if k.startswith("P")),
            max((k for k in t["pmax"] if k.startswith("P")), key=lambda k: t["pmax"][k])[1:],
            max(v for k, v in t["pmax"].items() if k.startswith("O")), t["pen"] * 1e3, r["ccx_s"]))
        print("  face-mean pressure per contact: %s" % {k: round(v) for k, v in t["pmax"].items()})
    with tempfile.TemporaryDirectory() as tmp:
        deck = rigid_bearing_deck(tmp)
        lt = {(b, c, k): ltca_run(a.ltca, deck, b, c, k) for b in ("elastic", "rigid")
              for c in ("absolute", "signed") for k in ("linearised", "exact")}
    rows = [("FE " + os.path.basename(d.rstrip("/")), dict(
        te=t["te_arcsec"], phi=t["phi"], pins={int(k): v for k, v in t["pins"].items()},
        opins={int(k): v for k, v in t["opins"].items()}, bearing=t["bearing"],
        pmax=max(v for k, v in t["pmax"].items() if k.startswith("P")),
        pmax_out=max(v for k, v in t["pmax"].items() if k.startswith("O")),
        contacts=sum(1 for v in t["pins"].values() if v > 0.5))) for d, r, t in fe]
    rows += [("ltca %s, %s, %s" % k, v) for k, v in lt.items()]
    print()
    print("| model | TE (output rotation), arcsec | disc rotation, arcsec | output minus disc, arcsec | ring pins loaded | largest ring-pin pressure, MPa | bearing force, N |")
    print("|---|---|---|---|---|---|---|")
    for name, v in rows:
        print("| %s | %.2f | %.2f | %.2f | %d | %.0f | %.0f |" % (name, v["te"], v["phi"], -v["te"] - v["phi"], v["contacts"],
                                                               v["pmax"], v["bearing"]))
    pins = sorted(set(j for _, v in rows for j, f in v["pins"].items() if f > 0.5))
    opins = sorted(set(j for _, v in rows for j, f in v["opins"].items() if f > 0.5))
    print()
    print("| model | " + " | ".join("pin %d" % j for j in pins) + " | " + " | ".join("output %d" % j for j in opins) + " |")
    print("|---|" + "---|" * (len(pins) + len(opins)))
    for name, v in rows:
        print("| %s | " % name + " | ".join("%.1f" % v["pins"].get(j, 0.0) for j in pins) + " | " +
              " | ".join("%.1f" % v["opins"].get(j, 0.0) for j in opins) + " |")
    for name, v in rows:
        if "pmax_out" in v:
            print("%s: largest output-pin (hole wall) pressure, face means, %.0f MPa" % (name, v["pmax_out"]))


if __name__ == "__main__":
    main()
