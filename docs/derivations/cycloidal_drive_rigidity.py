#!/usr/bin/env python3
"""The torsional rigidity of cases/stage/cycloidal_drive.toml, derived here from first principles
(issue 46): an independent check of `ltca stiffness cases/stage/cycloidal_drive.toml`, sharing no
code with ltca, only the deck's data and the documented laws and definitions.

    /usr/bin/python3 docs/derivations/cycloidal_drive_rigidity.py [--positions N] [--convex-holes]

(numpy only; about 10 s for the deck's 120 positions.) It prints the stage's rigidity (the mean
over the positions of T / (a_drive + a_coast), docs/stiffness.md), with the output pins in their
holes as the conformal line contact of a cylinder in a hole, or with --convex-holes as two convex
cylinders (the law ltca used under rho_convention = "absolute" before issue 46).

The model, written from the deck (all lengths mm, forces N, moments N*mm, angles rad):

Geometry. z_p = 40 pins of radius r_p = 3 on R_p = 64; a disc of z_c = 39 teeth, eccentricity
e = 1.3, face B = 12, ground as the envelope of a generating pin of radius r_g = r_p - 0.004 on a
circle R_g = R_p - 0.017 ([modification]). With the ring fixed and the crank at theta the disc
centre is at O = e exp(i theta) and the disc has turned by -theta / z_c, so a pin on R_g at angle
alpha sits, in the disc's frame, at exp(i theta / z_c) (R_g exp(i alpha) - e exp(i theta)); since
exp(i z_p alpha_j) = 1 every pin traces the one curve C(u) = exp(i u / z_c) (R_g - e exp(i u)),
pin j at u = theta + z_c alpha_j. The flank is C's inner parallel curve at distance r_g. A pin
centre P (radius R_p) is at the signed distance s from C (positive outwards), found by Newton's
method on (C(u) - P) . C'(u) = 0 from that u; its gap is s + r_g - r_p, its contact normal the
outward normal N of C at the foot point (to the pin), and the flank's radius of curvature
rho_t - r_g (rho_t = |C'|^3 / (C' x C''), signed: + convex).

Unknowns, per load: the disc's translation t, its rotation phi (both from the nominal pose), and
the output member's rotation psi; the input (eccentric) is held. Linearised kinematics about the
nominal pose (ltca's default `[solver] kinematics`):
- ring pin i: approach n_i . t + phi (Q_i - O) x n_i - c_i, Q_i its contact point;
- output pin j, centre P_j = R_w exp(i (alpha_j + beta)) on the output member (beta = -theta / z_c,
  the member turned as the disc: the W mechanism), in the hole H_j = O + R_w exp(i (alpha_j + beta))
  of the disc: the pin touches the hole on the line of centres, n_j = (P_j - H_j) / |P_j - H_j|
  (= -exp(i theta), |P_j - H_j| = e), approach (e - (r_h - r_w)) + n_j . (psi k x P_j - t
  - phi k x (H_j - O));
- roller k of the eccentric bearing at theta + 2 pi k / 14: the eccentric relative to the disc's
  bore is u = -t, approach u . e_k - c.

Laws.
- Ring pin on the flank: the line contact of two cylinders (Liu 2021 eq. 22-25; Johnson, Contact
  Mechanics, section 4.2(b)): delta = (2F / (pi B)) [C_c (ln(4 rho_c / b) - 1/2)
  + C_p (ln(4 r_p / b) - 1/2)], b = sqrt(4 F rho* / (pi B E*)), C = (1 - nu^2) / E,
  1/E* = C_c + C_p; rho* under the deck's rho_convention = "absolute": 1/rho* = |kappa_c| + 1/r_p;
  |rho_c| capped at R_p = 64 in the logarithm (ltca's log_radius_cap default, docs/contact.md).
- Output pin in its hole: the same line contact, the pin (r_w = 5) inside the concave hole
  (r_h = 6.32) of the disc: Johnson section 4.1's relative curvature with the concave radius
  negative, 1/rho* = 1/r_w - 1/r_h (rho* = 23.94); --convex-holes: 1/r_w + 1/r_h (2.79). The
  hole's radius enters its body's logarithm.
- Roller between the eccentric and the bore: Palmgren's line contact (Harris and Kotzalas,
  Rolling Bearing Analysis): delta = 3.84e-5 Q^0.9 / l^0.8 per raceway, two raceways in series,
  l = 10, radial play c = 0.005.
The balance is the minimum of the potential energy sum_e U_e(delta_e) - T psi (U_e = int F
d delta: F delta - int delta dF), found by a damped Newton method to 1e-12 of the twist.

Rigidity (docs/stiffness.md, the catalogue's b / a): on each flank a = the twist between 50 % and
100 % of T = 206 N*m; at a crank the stage's figure is T / (a_drive + a_coast) in N*m/arcmin;
ltca's summary is the mean over the sweep's positions (0 to 357 deg in 3 deg steps).
"""
import argparse
import math
import sys

import numpy as np

# --- the deck: cases/stage/cycloidal_drive.toml ----------------------------------------------------
ZP, ZC = 40, 39
RP, RRP, ECC, WIDTH = 64.0, 3.0, 1.3, 12.0
DRP, DRRP = -0.017, -0.004                          # [modification] pin_circle_radius_mm, pin_radius_mm
E_MOD, NU = 206000.0, 0.3                           # [material], disc and pins alike
OUT_COUNT, OUT_CIRCLE, OUT_PIN, OUT_HOLE = 8, 40.0, 5.0, 6.32
ROLLERS, ROLLER_LENGTH, PLAY = 14, 10.0, 0.005
TORQUE = 206.0e3                                    # N*mm
LOG_CAP = RP                                        # |rho_c| cap in the logarithm
ARCMIN = math.pi / (180.0 * 60.0)

COMPLIANCE = (1.0 - NU * NU) / E_MOD                # C = (1 - nu^2) / E, both bodies


# --- the line contact of two cylinders ---------------------------------------------------------------
class LineContact:
    """delta(F) = (2F / (pi B)) [C_1 (ln(4 R_1 / b) - 1/2) + C_2 (ln(4 R_2 / b) - 1/2)],
    b = sqrt(4 F rho / (pi B E*)): arrays of radii (R_1, R_2, rho), one entry per contact."""

    def __init__(self, r1, r2, rho, length):
        self.r1, self.r2, self.rho, self.length = np.asarray(r1, float), np.asarray(r2, float), np.asarray(rho, float), length
        self.c = 2.0 * COMPLIANCE  # C_1 + C_2
        # delta = (2F / (pi B)) [a - (c / 2) ln F] with b = b1 sqrt(F):
        b1 = np.sqrt(4.0 * self.rho * self.c / (math.pi * length))
        self.a = COMPLIANCE * (np.log(4.0 * self.r1 / b1) - 0.5) + COMPLIANCE * (np.log(4.0 * self.r2 / b1) - 0.5)
        self.x_max = 2.0 * self.a / self.c - 1.0  # ln of the largest force (delta rises up to it)

    def approach(self, f):
        b = np.sqrt(4.0 * f * self.rho * self.c / (math.pi * self.length))
        return 2.0 * f / (math.pi * self.length) * (COMPLIANCE * (np.log(4.0 * self.r1 / b) - 0.5)
                                                    + COMPLIANCE * (np.log(4.0 * self.r2 / b) - 0.5))

    def force(self, delta):
        """F(delta) for delta > 0 (0 elsewhere), by Newton's method on x = ln F (delta(x) increases
        and is concave below x_max), with its stiffness dF/d delta and the energy int F d delta."""
        delta = np.asarray(delta, float)
        on = delta > 0.0
        f = np.zeros_like(delta)
        k = np.zeros_like(delta)
        u = np.zeros_like(delta)
        if not on.any():
            return f, k, u
        a, xm, d = self.a[on], self.x_max[on], delta[on]
        g = 2.0 / (math.pi * self.length)
        x = np.minimum(np.log(d / (g * np.maximum(a, 1e-300))) + 1.0, xm - 1e-9)
        for _ in range(100):
            ex = np.exp(x)
            val = g * ex * (a - 0.5 * self.c * x) - d
            slope = g * ex * (a - 0.5 * self.c * x - 0.5 * self.c)
            step = np.where(slope > 0.0, val / np.where(slope > 0.0, slope, 1.0), 0.0)  # 0: at the law's largest force
            x_new = np.minimum(x - step, xm - 1e-12)
            if np.all(np.abs(x_new - x) < 1e-15 * np.maximum(1.0, np.abs(x))):
                x = x_new
                break
            x = x_new
        ff = np.exp(x)
        dddf = g * (a - 0.5 * self.c * x - 0.5 * self.c)
        # int_0^F delta df = g [a F^2 / 2 - (c / 2) (F^2 ln F / 2 - F^2 / 4)]
        comp = g * (0.5 * a * ff * ff - 0.5 * self.c * (0.5 * ff * ff * x - 0.25 * ff * ff))
        f[on], k[on], u[on] = ff, 1.0 / dddf, ff * d - comp
        return f, k, u


def palmgren(delta):
    """Q, dQ/d delta and int Q d delta of a roller between two raceways: delta = 2 * 3.84e-5
    Q^0.9 / l^0.8, so Q = K delta^(10/9) with K = (7.68e-5)^(-10/9) l^(8/9)."""
    kn = (7.68e-5) ** (-10.0 / 9.0) * ROLLER_LENGTH ** (8.0 / 9.0)
    d = np.maximum(delta, 0.0)
    return kn * d ** (10.0 / 9.0), kn * (10.0 / 9.0) * d ** (1.0 / 9.0), kn * (9.0 / 19.0) * d ** (19.0 / 9.0)


# --- the flank: distance from a pin centre to the generating curve ------------------------------------
RG, RRG = RP + DRP, RRP + DRRP


def curve(u):
    """C(u) = exp(i u / z_c) (R_g - e exp(i u)) and its first two derivatives (complex)."""
    w = np.exp(1j * u / ZC)
    v = np.exp(1j * u)
    c = w * (RG - ECC * v)
    c1 = w * (1j / ZC * (RG - ECC * v) - 1j * ECC * v)
    c2 = w * (-(1.0 / ZC ** 2) * (RG - ECC * v) + 2.0 * ECC * v / ZC + ECC * v)
    return c, c1, c2


def foot(p, u):
    """Newton's method on g(u) = Re((C(u) - p) conj(C'(u))) from u: the foot point on C."""
    for _ in range(50):
        c, c1, c2 = curve(u)
        g = np.real((c - p) * np.conj(c1))
        dg = np.abs(c1) ** 2 + np.real((c - p) * np.conj(c2))
        step = g / dg
        u = u - step
        if np.all(np.abs(step) < 1e-15):
            break
    return u


def ring_contacts(theta, t=0j, phi=0.0):
    """Every ring pin at crank theta, the disc moved by t (complex) and turned by phi from its
    nominal pose: the gap c, the normal n (fixed frame, to the pin), the arm (P - O) x n about the
    disc's centre O (d approach = n . dt + arm d phi) and the flank's signed radius of curvature."""
    alpha = 2.0 * math.pi * np.arange(ZP) / ZP
    turn = np.exp(1j * (theta / ZC - phi))            # fixed frame -> disc frame
    centre = ECC * np.exp(1j * theta) + t
    pins_fixed = RP * np.exp(1j * alpha)
    p = turn * (pins_fixed - centre)                  # the pins in the disc's frame
    u = foot(p, theta + ZC * alpha)
    c, c1, c2 = curve(u)
    tangent = c1 / np.abs(c1)
    normal = -1j * tangent                            # C runs counterclockwise: outward is -i T
    s = np.real((p - c) * np.conj(normal))
    gap = s + RRG - RRP
    rho_t = np.abs(c1) ** 3 / np.imag(np.conj(c1) * c2)  # signed, + convex
    rho_flank = rho_t - RRG
    n_fixed = normal / turn
    arm = np.imag(np.conj(pins_fixed - centre) * n_fixed)  # (P - O) x n: the normal passes through P
    return gap, n_fixed, arm, rho_flank


# --- the stage at one crank ---------------------------------------------------------------------------
class Stage:
    """The elements at crank theta. Linearised kinematics: every approach affine in
    q = (t_x, t_y, phi, psi), frozen at the nominal pose; exact: re-evaluated at q (the flank's
    foot point, normal, arm and curvature; the output pins' line of centres)."""

    def __init__(self, theta, convex_holes, exact=False):
        self.theta, self.exact = theta, exact
        self.hole_inv = 1.0 / OUT_PIN + (1.0 if convex_holes else -1.0) / OUT_HOLE
        self.out_law = LineContact(np.full(OUT_COUNT, OUT_HOLE), np.full(OUT_COUNT, OUT_PIN),
                                   np.full(OUT_COUNT, 1.0 / self.hole_inv), WIDTH)
        phi_k = theta + 2.0 * math.pi * np.arange(ROLLERS) / ROLLERS
        self.roll_rows = np.stack([-np.cos(phi_k), -np.sin(phi_k), np.zeros(ROLLERS), np.zeros(ROLLERS)], axis=1)
        self.nominal = self.elements(np.zeros(4))

    def elements(self, q):
        """(rows, approaches at q, law) of the ring pins and of the output pins at the pose q."""
        t = complex(q[0], q[1])
        gap, n, arm, rho_flank = ring_contacts(self.theta, t, q[2])
        ring_rows = np.stack([n.real, n.imag, arm, np.zeros_like(arm)], axis=1)
        kappa = np.abs(1.0 / rho_flank)                   # rho_convention = "absolute"
        ring_law = LineContact(np.minimum(np.abs(rho_flank), LOG_CAP), np.full(ZP, RRP), 1.0 / (kappa + 1.0 / RRP), WIDTH)

        beta = -self.theta / ZC
        centre = ECC * np.exp(1j * self.theta) + t
        alpha = 2.0 * math.pi * np.arange(OUT_COUNT) / OUT_COUNT
        pin = OUT_CIRCLE * np.exp(1j * (alpha + beta + q[3]))
        arm_h = OUT_CIRCLE * np.exp(1j * (alpha + beta + q[2]))
        d = pin - (centre + arm_h)
        nj = d / np.abs(d)
        # d approach = n . (d psi k x P - dt - d phi k x (H - O)), approach |P - H| - (r_h - r_w)
        out_rows = np.stack([-nj.real, -nj.imag, -np.real(nj * np.conj(1j * arm_h)), np.real(nj * np.conj(1j * pin))], axis=1)
        out_delta = np.abs(d) - (OUT_HOLE - OUT_PIN)
        return ((ring_rows, -gap, ring_law), (out_rows, out_delta, self.out_law))

    def energy(self, q, torque):
        """The potential, its gradient and (Gauss-Newton under exact kinematics) Hessian at q."""
        total, grad, hess = -torque * q[3], np.array([0.0, 0.0, 0.0, -torque]), np.zeros((4, 4))
        parts = self.elements(q) if self.exact else self.nominal
        for rows, delta, law in (*parts, (self.roll_rows, None, None)):
            if law is None:
                delta = rows @ q - PLAY
                f, k, u = palmgren(delta)
            else:
                if not self.exact:
                    delta = delta + rows @ q
                f, k, u = law.force(delta)
            total += u.sum()
            grad += rows.T @ f
            hess += (rows * k[:, None]).T @ rows
        return total, grad, hess

    def solve(self, torque, q):
        """Damped Newton (Levenberg-Marquardt, scaled) on the convex potential, from q; under exact
        kinematics then Newton's method on the balance (the gradient) from there."""
        scale = np.array([1.0, 1.0, RP, RP])          # rotations as arcs on the pin circle
        exact, self.exact = self.exact, False
        lam = 1.0
        pi0, g, h = self.energy(q, torque)
        for _ in range(500):
            d = np.maximum(np.diag(h) / scale ** 2, 1e3)
            step = np.linalg.solve(h + lam * np.diag(d * scale ** 2), -g)
            pi1, g1, h1 = self.energy(q + step, torque)
            if pi1 <= pi0 + 1e-14 * abs(pi0):
                q, pi0, g, h = q + step, pi1, g1, h1
                lam = max(lam / 10.0, 1e-12)
                if np.max(np.abs(step * scale)) < 1e-13:
                    break
            else:
                lam *= 10.0
        else:
            raise RuntimeError("no convergence")
        self.exact = exact
        if not exact:
            return q
        for _ in range(200):
            _, g, h = self.energy(q, torque)
            step = np.linalg.solve(h, -g)
            q = q + step
            if np.max(np.abs(step * scale)) < 1e-13:
                return q
        raise RuntimeError("no convergence under exact kinematics")


def rigidity(theta, convex_holes, exact):
    st = Stage(theta, convex_holes, exact)
    twist = {}
    for sense in (1.0, -1.0):
        q = np.zeros(4)
        for level in (0.5, 1.0):
            q = st.solve(sense * level * TORQUE, q)
            twist[(sense, level)] = q[3]
    a_drive = twist[(1.0, 1.0)] - twist[(1.0, 0.5)]
    a_coast = twist[(-1.0, 0.5)] - twist[(-1.0, 1.0)]
    return (TORQUE / 1e3) / ((a_drive + a_coast) / ARCMIN), a_drive / ARCMIN, a_coast / ARCMIN


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--positions", type=int, default=120, help="crank angles 0, 3, ..., 357 deg (the deck's sweep)")
    parser.add_argument("--convex-holes", action="store_true", help="the output pins as two convex cylinders (the old law)")
    parser.add_argument("--exact", action="store_true", help="exact kinematics (the contacts re-evaluated at the loaded poses)")
    args = parser.parse_args()
    # Checks of the pieces against their closed forms.
    law = LineContact([6.32], [5.0], [23.9], WIDTH)
    for f in (1.0, 100.0, 5000.0):
        got, _, _ = law.force(law.approach(np.array([f])))
        assert abs(got[0] - f) < 1e-10 * f, (got, f)
    gap0, _, _, rho0 = ring_contacts(0.0)  # pin 0 at the root of a tooth space at crank 0
    print(f"checks: root of the flank at crank 0: radius {rho0[0]:.4f} mm, gap {gap0[0] * 1e3:.4f} um "
          f"(R_g - R_p + r_p - r_g = {(RP - RG - RRP + RRG) * 1e3:.4f} um expected there)", file=sys.stderr)
    cranks = [math.radians(3.0 * i * 120 / args.positions) for i in range(args.positions)]
    values = [rigidity(t, args.convex_holes, args.exact) for t in cranks]
    r = np.array([v[0] for v in values])
    drive = np.array([0.5 * TORQUE / 1e3 / v[1] for v in values])
    coast = np.array([0.5 * TORQUE / 1e3 / v[2] for v in values])
    law_name = "two convex cylinders, 1/rho* = 1/r_w + 1/r_h" if args.convex_holes else "conformal, 1/rho* = 1/r_w - 1/r_h"
    print(f"output pins in holes: {law_name}; {'exact' if args.exact else 'linearised'} kinematics")
    print(f"{args.positions} positions over the crank turn: rigidity {r.mean():.4f} N*m/arcmin (mean; "
          f"{r.min():.4f} .. {r.max():.4f} over the positions); drive / coast flank {drive.mean():.4f} / "
          f"{coast.mean():.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
