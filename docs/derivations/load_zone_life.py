#!/usr/bin/env python3
"""The load-zone life of a stage's roller bearings, recomputed from ltca's printed roller loads.

Independent of ltca's code (the Python standard library only): reads the deck (TOML) and the
JSON of `ltca solve <deck> --json -`, and recomputes from each position's `roller_load_n`
(docs/stage.md, "Load-zone life"):

- which ring turns against the load, from the printed bearing load's direction over the sweep:
  turning with the eccentric (the crank angle), the outer ring; standing, the inner ring;
- per raceway the equivalent roller load, (1/Z sum Q^4)^(1/4) for the raceway turning against
  the load, (1/Z sum Q^4.5)^(1/4.5) for the other;
- Q_c,in / Q_c,out = ((1 - g) / (1 + g))^(29/27 + 1/4), g = D_w / d_m (Harris and Kotzalas);
- L = (Q_c / Q_e)^4 per raceway, combined with exponent 9/8, Palmgren-Miner over the positions;
- the reference: the same bearing without play under a stationary radial load, inner ring
  turning, averaged over 16 roller phases of one pitch. Each reference state is solved here by
  bisection on the direction of the inner ring's displacement (the roller loads without play are
  proportional to cos^(10/9) of their angle to it), not by ltca's Newton method;
- P_lz = (damage / reference damage)^(1/4), L = (C / P_lz)^(10/3), hours at |1 - 1/I| of the crank.

It prints, per bearing, the load-zone life and the basic ISO 281 life (from the printed bearing
loads) with their ratio, and the same ratio had the inner ring turned against the load.

    build/release/ltca solve cases/stage/cycloidal_drive.toml --json - > /tmp/s.json
    python3 docs/derivations/load_zone_life.py cases/stage/cycloidal_drive.toml /tmp/s.json [--check 1e-6]

With --check TOL it exits 1 unless every recomputed figure (load-zone and basic life, hours) is
within TOL (relative) of ltca's.
"""
import json
import math
import sys
import tomllib

PHASES = 16


def damage(loads, ratio, turning):
    """One load state's damage per revolution, Q_c,out = 1 N."""
    z = len(loads)
    m4 = sum(q ** 4 for q in loads) / z
    m45 = sum(q ** 4.5 for q in loads) / z
    q_turning, q_standing = m4 ** 0.25, m45 ** (1.0 / 4.5)
    q_in, q_out = (q_turning, q_standing) if turning == "inner" else (q_standing, q_turning)
    l_in, l_out = (ratio / q_in) ** 4, (1.0 / q_out) ** 4
    return (l_in ** -1.125 + l_out ** -1.125) ** (8.0 / 9.0)


def reference_loads(z, phase):
    """Roller loads without play under 1 N along +x, rollers at phase + 2 pi j / z."""
    angles = [phase + 2.0 * math.pi * j / z for j in range(z)]

    def loads(beta):  # displacement direction beta: Q_j ~ max(cos(psi_j - beta), 0)^(10/9)
        return [max(math.cos(a - beta), 0.0) ** (10.0 / 9.0) for a in angles]

    def force_angle(beta):
        q = loads(beta)
        return math.atan2(sum(x * math.sin(a) for x, a in zip(q, angles)), sum(x * math.cos(a) for x, a in zip(q, angles)))

    lo, hi = -0.5, 0.5  # the force's direction rises with the displacement's
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if force_angle(mid) > 0.0:
            hi = mid
        else:
            lo = mid
    q = loads(0.5 * (lo + hi))
    fx = sum(x * math.cos(a) for x, a in zip(q, angles))
    return [x / fx for x in q]


def main():
    deck = tomllib.load(open(sys.argv[1], "rb"))
    solve = json.load(open(sys.argv[2]))
    tol = float(sys.argv[sys.argv.index("--check") + 1]) if "--check" in sys.argv else None
    b = deck["bearing"]
    z, d, dm, c = b["roller_count"], b["roller_diameter_mm"], b["pitch_diameter_mm"], b["dynamic_load_rating_n"]
    g = d / dm
    ratio = ((1.0 - g) / (1.0 + g)) ** (29.0 / 27.0 + 0.25)
    pair = deck["pair"]
    transmission = -pair["tooth_count"] / (pair["pin_count"] - pair["tooth_count"])
    rpm = deck["operation"]["input_speed_rpm"] * abs(1.0 - 1.0 / transmission)
    reference = {t: sum(damage(reference_loads(z, 2.0 * math.pi * m / (PHASES * z)), ratio, t) for m in range(PHASES)) / PHASES
                 for t in ("inner", "outer")}
    positions = [p for p in solve["positions"] if p["status"] == "success"]
    if solve["summary"]["closed_period"]:
        positions = positions[:-1]
    stage = solve["summary"]["stage"]
    states = {}  # bearing index -> list of roller-load lists, disc-major
    loads = {}
    directions = {}
    for p in positions:
        k = 0
        for disc in p["stage"]["discs"]:
            for rollers, load, direction in zip(disc["roller_load_n"], disc["bearing_load_n"], disc["bearing_load_direction_deg"]):
                states.setdefault(k, []).append(rollers)
                loads.setdefault(k, []).append(load)
                directions.setdefault(k, []).append(direction)
                k += 1
    # Which ring turns against the load: the load's direction (fixed frame) unwrapped over the
    # sweep against the eccentric's (the crank angle). Turning with the eccentric, the inner ring,
    # it leaves the outer ring turning against it, as ltca says.
    swept = positions[-1]["crank_deg"] - positions[0]["crank_deg"]
    turning = {}
    for k, angles in directions.items():
        turned = 0.0
        for a, b in zip(angles, angles[1:]):
            turned += (b - a + 180.0) % 360.0 - 180.0
        with_eccentric, standing = abs(turned - swept) < 30.0, abs(turned) < 30.0
        turning[k] = "outer" if with_eccentric else ("inner" if standing else None)
        print(f"bearing {k}: its load turns {turned:.2f} deg over {swept:.2f} deg of crank: "
              + ("with the eccentric, the outer ring turns against it" if with_eccentric else
                 "it stands, the eccentric (inner ring) turns against it" if standing else "neither: no turning raceway"))
        if tol is not None and turning[k] != stage["turning_raceway"][k]:
            print(f"FAIL: ltca's turning raceway {stage['turning_raceway'][k]}")
            return 1
    hours = lambda life: 1e6 * life / (60.0 * rpm)
    worst = 0.0
    print(f"g = {g:.6g}, Q_c,in / Q_c,out = {ratio:.9g}, bearing speed {rpm:.9g} rpm, {len(positions)} positions")
    for k in sorted(states):
        p_m = (sum(x ** (10.0 / 3.0) for x in loads[k]) / len(loads[k])) ** 0.3
        basic = hours((c / p_m) ** (10.0 / 3.0))
        lives = {}
        for ring in ("outer", "inner"):
            # Either ring turning against the load: the reference is the same (its inner ring
            # turns), only the raceways' exponents of the states swap.
            mean = sum(damage(q, ratio, ring) for q in states[k]) / len(states[k])
            p_lz = (mean / reference["inner"]) ** 0.25
            lives[ring] = hours((c / p_lz) ** (10.0 / 3.0))
        ring, other = turning[k] or "outer", "inner" if (turning[k] or "outer") == "outer" else "outer"
        printed, printed_basic = stage["load_zone_life_hours"][k], stage["l10_hours"][k]
        err = max(abs(lives[ring] / printed - 1.0), abs(basic / printed_basic - 1.0))
        worst = max(worst, err)
        print(f"bearing {k}: load-zone life {lives[ring]:.9g} h (ltca {printed:.9g}; the {ring} ring turning), basic "
              f"{basic:.9g} h (ltca {printed_basic:.9g}); ratio {lives[ring] / basic:.4f} (the {other} ring turning: "
              f"{lives[other] / basic:.4f}); largest relative difference {err:.3g}")
    if tol is not None and not worst <= tol:
        print(f"FAIL: {worst:.3g} > {tol:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
