"""`ltca geometry DECK --dxf FILE` read back by an independent reader (ezdxf): the disc's profile
within 0.1 um of the analytic curve at every vertex and between them (docs/export.md), the
analytic curve evaluated here from the cycloid's equations (docs/conventions.md: the pin-centre
locus q(u) = R'(cos u, sin u) - e (cos Ze u, sin Ze u), Ze = z_p / d, its equidistant at r'
toward the material for d > 0), the layers, units and the elements of [output] and [pins]."""
import math
import os
import pathlib
import subprocess
import tomllib

import numpy as np
import pytest

ezdxf = pytest.importorskip("ezdxf")

LTCA = os.environ.get("LTCA_EXE", "build/release/ltca")
ROOT = pathlib.Path(__file__).resolve().parents[2]
TOL = 1e-4  # mm: 0.1 um


class Cycloid:
    """The real profile of tooth space 0 from its equations, in NumPy (no ltca code)."""

    def __init__(self, deck):
        pair, mod = deck["pair"], deck.get("modification", {})
        errors = deck.get("errors", {})
        self.zp, self.zc = pair["pin_count"], pair["tooth_count"]
        self.d = self.zp - self.zc
        assert self.d > 0, "the check below is written for a disc (d > 0)"
        self.R = pair["pin_circle_radius_mm"] + mod.get("pin_circle_radius_mm", 0.0)
        # A uniform profile layer adds material: the equidistant moves toward the pins.
        self.r = pair["pin_radius_mm"] + mod.get("pin_radius_mm", 0.0) - errors.get("cycloid_profile_layer_mm", 0.0)
        self.e = pair["eccentricity_mm"]
        self.rotation = math.radians(mod.get("rotation_deg", 0.0))
        self.ze = self.zp / self.d
        self.phi_max = self._half_width()
        # A rounding-only tip relief of a sharp-tipped pair (d >= 2): an arc of radius rho tangent to
        # both flanks, its centre on the tooth's axis at x(u_j) - rho n(u_j); the flank ends at u_j.
        self.rho = mod.get("tip_rounding_radius_mm", 0.0)
        assert mod.get("tip_truncation_mm", 0.0) == 0.0, "the check below knows the rounding arc alone"
        self.u_j, self.centre = self.phi_max, None
        if self.rho > 0.0:
            assert self.d >= 2
            g = lambda u: math.atan2(*self._arc_centre(u)[::-1]) - math.pi / self.zc
            self.u_j = self._bisect(g, 1e-6, self.phi_max)
            self.centre = self._arc_centre(self.u_j)

    def position(self, u):
        u = np.asarray(u, dtype=float)
        q = np.stack([self.R * np.cos(u) - self.e * np.cos(self.ze * u), self.R * np.sin(u) - self.e * np.sin(self.ze * u)], -1)
        q1 = np.stack([-self.R * np.sin(u) + self.e * self.ze * np.sin(self.ze * u),
                       self.R * np.cos(u) - self.e * self.ze * np.cos(self.ze * u)], -1)
        n_in = np.stack([-q1[..., 1], q1[..., 0]], -1) / np.linalg.norm(q1, axis=-1)[..., None]
        return q + self.r * n_in

    def normal(self, u):
        """Unit normal out of the material (toward the pin): the locus' right normal for d > 0."""
        u = np.asarray(u, dtype=float)
        q1 = np.stack([-self.R * np.sin(u) + self.e * self.ze * np.sin(self.ze * u),
                       self.R * np.cos(u) - self.e * self.ze * np.cos(self.ze * u)], -1)
        return np.stack([q1[..., 1], -q1[..., 0]], -1) / np.linalg.norm(q1, axis=-1)[..., None]

    def _arc_centre(self, u):
        return self.position(u) - self.rho * self.normal(u)

    @staticmethod
    def _bisect(f, lo, hi):
        assert (f(lo) < 0) != (f(hi) < 0)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if (f(mid) < 0) == (f(lo) < 0):
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)

    def _half_width(self):
        # Where the profile reaches the tooth's axis, polar angle pi / z_c (pi / z_c itself for d = 1).
        if self.d == 1:
            return math.pi / self.zc
        lo, hi = 1e-9, self.d * math.pi / self.zc
        f = lambda u: math.atan2(*self.position(u)[::-1]) - math.pi / self.zc
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if (f(mid) < 0) == (f(lo) < 0):
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)

    def distance(self, points):
        """Distance of each point (N x 2, body frame) to the profile: into the space its polar angle
        falls in, then the foot point by golden section about the u of the same polar angle."""
        p = np.asarray(points, dtype=float)
        pitch = 2.0 * math.pi / self.zc
        angle = np.arctan2(p[:, 1], p[:, 0]) - self.rotation
        k = np.round(angle / pitch)
        turn = -(k * pitch + self.rotation)
        local = np.stack([np.cos(turn) * p[:, 0] - np.sin(turn) * p[:, 1], np.sin(turn) * p[:, 0] + np.cos(turn) * p[:, 1]], -1)
        # u from the polar angle: the polar angle of x(u) rises with u across the space.
        table_u = np.linspace(-self.phi_max, self.phi_max, 20001)
        table = self.position(table_u)
        table_angle = np.arctan2(table[:, 1], table[:, 0])
        u0 = np.interp(np.arctan2(local[:, 1], local[:, 0]), table_angle, table_u)
        step = 3.0 * (table_u[1] - table_u[0])
        a = np.clip(u0 - step, -self.u_j, self.u_j)
        b = np.clip(u0 + step, -self.u_j, self.u_j)
        g = 0.5 * (math.sqrt(5.0) - 1.0)
        dist = lambda u: np.linalg.norm(self.position(u) - local, axis=-1)
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = dist(c), dist(d)
        for _ in range(80):
            left = fc < fd
            b = np.where(left, d, b)
            a = np.where(left, a, c)
            c_new = np.where(left, b - g * (b - a), d)
            d_new = np.where(left, c, a + g * (b - a))
            fc_new = np.where(left, dist(c_new), fd)
            fd_new = np.where(left, fc, dist(d_new))
            c, d, fc, fd = c_new, d_new, fc_new, fd_new
        flank = np.minimum(fc, fd)
        if self.centre is None:
            return flank
        # The rounding arcs of the two tips of the space, at +-pi / z_c.
        arcs = [np.abs(np.linalg.norm(local - np.array([self.centre[0], sign * self.centre[1]]), axis=-1) - self.rho)
                for sign in (1.0, -1.0)]
        return np.minimum(flank, np.minimum(*arcs))


def write_dxf(tmp_path, deck, *overrides):
    out = tmp_path / "disc.dxf"
    sets = [a for o in overrides for a in ("--set", o)]
    run = subprocess.run([LTCA, "geometry", str(ROOT / deck), *sets, "--dxf", str(out)], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return ezdxf.readfile(out)


def deck_with(deck, **edits):
    with open(ROOT / deck, "rb") as f:
        data = tomllib.load(f)
    for key, value in edits.items():
        section, name = key.split("__")
        data.setdefault(section, {})[name] = value
    return data


@pytest.mark.parametrize("deck,overrides,edits", [
    ("cases/stage/cycloidal_drive.toml", (), {}),  # d = 1, modified, output pins
    ("cases/chen2008/d2.toml", ("modification.pin_radius_mm=0.01", "modification.rotation_deg=0.01"),
     {"modification__pin_radius_mm": 0.01, "modification__rotation_deg": 0.01}),  # d = 2, sharp tips
    ("cases/chen2008/d2.toml", ("modification.tip_rounding_radius_mm=2", "modification.tip_truncation_mm=0"),
     {"modification__tip_rounding_radius_mm": 2.0}),  # d = 2, tips rounded
])
def test_the_dxf_profile_is_within_a_tenth_of_a_micrometre_of_the_cycloid(tmp_path, deck, overrides, edits):
    doc = write_dxf(tmp_path, deck, *overrides)
    assert doc.header["$INSUNITS"] == 4  # millimetres
    for layer in ("DISC_PROFILE", "BORE", "HOLES", "PIN_RING", "OUTPUT_PINS"):
        assert layer in doc.layers
    profiles = doc.modelspace().query('LWPOLYLINE[layer=="DISC_PROFILE"]')
    assert len(profiles) == 1
    line = profiles[0]
    assert line.closed
    vertices = np.array([(x, y) for x, y, *_ in line.get_points()])
    cycloid = Cycloid(deck_with(deck, **edits))
    # Every tooth space is drawn, and densely (a 0.1 um sagitta needs many points a space).
    assert len(vertices) > 40 * cycloid.zc
    at_vertices = cycloid.distance(vertices)
    nxt = np.roll(vertices, -1, axis=0)
    between = np.concatenate([vertices + (nxt - vertices) * t for t in (0.25, 0.5, 0.75)])
    at_chords = cycloid.distance(between)
    assert at_vertices.max() < 1e-6, at_vertices.max()  # on the curve (the text keeps 16 digits)
    assert at_chords.max() < TOL, at_chords.max()
    # The check can fail: every other vertex dropped, the chords stray beyond 0.1 um.
    coarse = vertices[::4]
    mid = 0.5 * (coarse + np.roll(coarse, -1, axis=0))
    assert cycloid.distance(mid).max() > TOL
    # Counter-clockwise (a positive area near the disc's): the shoelace area against pi r^2 bounds.
    x, y = vertices[:, 0], vertices[:, 1]
    area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    radii = np.hypot(x, y)
    assert math.pi * radii.min() ** 2 < area < math.pi * radii.max() ** 2


def test_the_dxf_places_the_pins_the_output_pins_and_their_holes(tmp_path):
    deck = "cases/stage/cycloidal_drive.toml"
    doc = write_dxf(tmp_path, deck)
    data = deck_with(deck)
    pair, out = data["pair"], data["output"]
    msp = doc.modelspace()
    pins = msp.query('CIRCLE[layer=="PIN_RING"]')
    assert len(pins) == pair["pin_count"]
    # At crank 0 the disc centre is at (e, 0) from the pin circle's: pin j at R_p (cos, sin)(2 pi j / z_p) - (e, 0).
    for j, c in enumerate(pins):
        psi = 2.0 * math.pi * j / pair["pin_count"]
        assert abs(c.dxf.center.x - (pair["pin_circle_radius_mm"] * math.cos(psi) - pair["eccentricity_mm"])) < 1e-9
        assert abs(c.dxf.center.y - pair["pin_circle_radius_mm"] * math.sin(psi)) < 1e-9
        assert abs(c.dxf.radius - pair["pin_radius_mm"]) < 1e-12
    holes = msp.query('CIRCLE[layer=="HOLES"]')
    output_pins = msp.query('CIRCLE[layer=="OUTPUT_PINS"]')
    assert len(holes) == out["count"] == len(output_pins)
    phase = math.radians(out.get("phase_deg", 0.0))
    for j, (h, w) in enumerate(zip(holes, output_pins)):
        a = 2.0 * math.pi * j / out["count"] + phase
        assert abs(h.dxf.center.x - out["circle_radius_mm"] * math.cos(a)) < 1e-9
        assert abs(h.dxf.center.y - out["circle_radius_mm"] * math.sin(a)) < 1e-9
        assert abs(h.dxf.radius - out["hole_radius_mm"]) < 1e-12
        assert abs(w.dxf.center.x - (out["circle_radius_mm"] * math.cos(a) - pair["eccentricity_mm"])) < 1e-9
        assert abs(w.dxf.radius - out["pin_radius_mm"]) < 1e-12
    assert len(msp.query('*[layer=="BORE"]')) == 0  # a rigid disc: no bore given


def test_the_dxf_draws_the_bore_an_elastic_disc_gives(tmp_path):
    doc = write_dxf(tmp_path, "cases/liu2021_table1.toml", 'disc.body="elastic"', "disc.bore_radius_mm=22")
    bores = doc.modelspace().query('CIRCLE[layer=="BORE"]')
    assert len(bores) == 1
    assert abs(bores[0].dxf.radius - 22.0) < 1e-12 and abs(bores[0].dxf.center.x) < 1e-12 and abs(bores[0].dxf.center.y) < 1e-12
