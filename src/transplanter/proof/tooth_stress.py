"""Tooth load and stress at a contact of the made teeth, measured on the outlines themselves (the
(n, 2) closed polygons in the gear frame, mm, vertices on the generated envelope): it holds tooth
by tooth for non-circular gears, where no two teeth are alike and a tooth's flanks are not mirrors.

**Local radius of curvature** (:func:`radius_of_curvature`): a quartic ``y(x)`` fitted by least
squares, in the frame of the tangent at the point, to the vertices within ``window`` of arc length
centred on it; ``κ = y''/(1 + y'²)^(3/2)`` there. Why: a fillet's curvature changes fast along it
(a circle fit over the same window is off by up to 1 %, a smaller window holds too few vertices),
and a centred window cancels the odd terms of that change. Accuracy (``tests/test_tooth_stress.py``):
circle and involute within 1e-5; a rack-cut fillet at its 30° point within 0.05 % of ISO's closed
form at the default window, 0.1 module. The window stops at a corner (edges turning by more than
30°: a tip corner) and takes at least three vertices each side. Sign: + convex (the centre of
curvature in the material), - concave (a fillet, a ring's flank).

**Hertz** (:func:`hertz_line_contact`): ``σ_H = √(F/(π b) (1/ρ1 + 1/ρ2) / ((1-ν1²)/E1 + (1-ν2²)/E2))``,
half width ``a = √(4 F ((1-ν1²)/E1 + (1-ν2²)/E2) / (π b (1/ρ1 + 1/ρ2)))``.

**Root bending** (:func:`root_stress`): ISO 6336-3 method B's critical section on one tooth's real
outline. The tooth runs between the bottoms of its two tooth spaces (least radius from the gear
centre; a ring's greatest). Its **centre line** passes through the middle of its root (midpoint of
the two space bottoms) and the middle of its tip (by arc length, of the outline within 0.02 m of
its highest point above the bottoms' chord). On *each fillet separately* the first point up from
the space bottom whose tangent makes 30° with the centre line (60° for a ring's teeth, as ISO
takes for internal gears) is found; ``s_Fn`` is the chord between the two. The load's bending
moment about the chord's middle is ``F h_F cos α_F``: ``α_F`` the angle between the load line and
the chord (ISO's α_Fen), ``h_F`` the lever (ISO's h_Fe). ``Y_F = 6 (h_F/m) cos α_F / ((s_Fn/m)²
cos α_n)``, ``Y_S = (1.2 + 0.13 L) q_s^(1/(1.21 + 2.3/L))``, L = s_Fn/h_F, q_s = s_Fn/(2 ρ_F), ρ_F
the loaded (tension) fillet's radius at its 30° point, and ``σ_F = F cos α_n/(b m) Y_F Y_S``. As
in ISO the radial (compressive) share is not subtracted (ISO's Y_S was fitted with it); it is
reported beside (``sigma_compressive``).

At a contact of a made pair, :mod:`~transplanter.proof.mesh_load` puts these together with the
normal force and the safety factors.

Examples
--------
A convex flank of 10 mm radius on a concave one of 30 mm (a ring), steel on steel:

>>> h = hertz_line_contact(1000.0, 10.0, 10.0, -30.0, STEEL, STEEL)
>>> round(h.sigma_h, 1), round(h.half_width, 4)
(490.1, 0.1299)
>>> c = 5.0 * np.stack([np.cos(t := np.linspace(0, 2 * np.pi, 721)[:-1]), np.sin(t)], axis=1)
>>> round(radius_of_curvature(c, (5.0, 0.0), 0.5), 5)
5.0

A 19-tooth gear (m = 4 mm, x = 0.5) cut by an ISO 53 rack (h_fP = 1.25 m, ρ_fP = 0.25 m), loaded
at a tip corner along the involute's normal there (ISO's Y_Fa = 2.2463, Y_Sa = 1.9147):

>>> from transplanter.geometry.pitch import PitchCurve
>>> from transplanter.geometry.rack_cutter import RackCutter
>>> from transplanter.geometry.teeth import generate
>>> rack = RackCutter(module=4.0, addendum=1.25, dedendum=1.8, tip_fillet=0.25)
>>> out = generate(PitchCurve.circle(38.0), rack, 19, shift=0.5, min_land=0.0).toothed_contour
>>> tip = 44.0 * np.array([np.cos(a := math.pi / 19 + 0.0207736), np.sin(a)])
>>> load = np.array([np.sin(a - 0.6239916), -np.cos(a - 0.6239916)])
>>> rs = root_stress(out, tip, 1000.0, 20.0, 4.0, direction=load)
>>> round(rs.y_f, 3), round(rs.y_s, 3), round(rs.s_fn / 4, 4)
(2.246, 1.915, 2.1873)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import GeometryError, SpecError, check_number

__all__ = [
    "STEEL",
    "Elastic",
    "HertzContact",
    "RootStress",
    "hertz_line_contact",
    "radius_of_curvature",
    "root_stress",
]

#: a turn between two edges above this is a corner (a tip corner), where no window crosses, degrees
CORNER_DEG = 30.0
#: the fit takes at least this many vertices on each side of the point
MIN_SIDE = 3
#: degree of the polynomial fitted to the outline about a point for its curvature
DEGREE = 4


@dataclass(frozen=True)
class Elastic:
    """Young's modulus ``e`` (MPa) and Poisson's ratio ``nu`` of a gear material."""

    e: float
    nu: float

    def __post_init__(self) -> None:
        check_number("e", self.e, 0.0, 1e7, low_open=True, unit="MPa")
        check_number("nu", self.nu, 0.0, 0.5, high_open=True)

    @property
    def compliance(self) -> float:
        """(1 - ν²)/E, 1/MPa."""
        return (1.0 - self.nu**2) / self.e


#: steel as ISO 6336-2 takes it for Z_E = 189.8 √MPa (E = 206 000 MPa, ν = 0.3)
STEEL = Elastic(206_000.0, 0.3)


@dataclass(frozen=True)
class HertzContact:
    """Hertz line contact: peak pressure ``sigma_h`` (MPa), half contact width (mm) and the
    equivalent radius ``rho`` (mm) of the two flanks, ``1/ρ = 1/ρ1 + 1/ρ2``."""

    sigma_h: float
    half_width: float
    rho: float


@dataclass(frozen=True)
class RootStress:
    """Root bending of one tooth, ISO 6336-3 method B on its outline (mm, MPa, degrees).

    Attributes
    ----------
    s_fn : float
        Chord between the two 30° (60°) tangent points, mm.
    h_f : float
        Bending lever of the load to the critical section, mm (ISO's h_Fe).
    alpha_f : float
        Load angle (ISO's α_Fen), degrees.
    rho_f : float
        Radius of the loaded (tension) fillet at its tangent point, mm; ``rho_other`` the other's.
    y_f, y_s : float
        ISO's form factor (referred to module ``m`` and ``cos α_n``) and stress correction factor.
    sigma_f : float
        Root stress F cos α_n/(b m) Y_F Y_S, MPa; ``sigma_compressive`` the radial share not included.
    points : (2, 2) float
        The two tangent points (loaded fillet first), gear frame, mm.
    centre_line : (2, 2) float
        The tooth's centre line: the middle of its root, then the middle of its tip, mm.
    """

    s_fn: float
    h_f: float
    alpha_f: float
    rho_f: float
    rho_other: float
    y_f: float
    y_s: float
    sigma_f: float
    sigma_compressive: float
    points: np.ndarray
    centre_line: np.ndarray


def _cross(a, b):
    """z of the cross product of 2-vectors (arrays of them too)."""
    a, b = np.asarray(a), np.asarray(b)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _closed(outline, name: str, inside: bool) -> np.ndarray:
    """The outline as (n, 2) without the closing repeat, turned so the material is on the left."""
    try:
        p = np.asarray(outline, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SpecError(f"{name} must be an (n, 2) array of points, mm") from exc
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 4 or not np.all(np.isfinite(p)):
        raise SpecError(f"{name} must be a finite (n, 2) array of at least 4 points, mm; got shape {p.shape}")
    if np.allclose(p[0], p[-1]):
        p = p[:-1]
    area = 0.5 * float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
    return p if (area > 0) == inside else p[::-1].copy()


def _point(value, name: str) -> np.ndarray:
    p = np.asarray(value, dtype=float)
    if p.shape != (2,) or not np.all(np.isfinite(p)):
        raise SpecError(f"{name} must be a finite (x, y) pair, got {value!r}")
    return p


class _Ring:
    """A closed outline with arc length: the foot of a point, and walks along it."""

    def __init__(self, p: np.ndarray):
        self.p = p
        self.n = len(p)
        self.edge = np.roll(p, -1, axis=0) - p
        self.length = np.linalg.norm(self.edge, axis=1)
        self.s = np.concatenate([[0.0], np.cumsum(self.length)])
        self.total = float(self.s[-1])
        t = self.edge / self.length[:, None]
        back = np.roll(t, 1, axis=0)
        turn = np.arctan2(_cross(back, t), np.einsum("ij,ij->i", back, t))
        self.corner = np.abs(turn) > math.radians(CORNER_DEG)  # at vertex i, between edges i-1 and i

    def foot(self, q: np.ndarray) -> tuple[int, float]:
        """Edge index and arc length of the nearest point of the outline to ``q``."""
        d = q - self.p
        u = np.clip(np.einsum("ij,ij->i", d, self.edge) / self.length**2, 0.0, 1.0)
        gap = np.linalg.norm(d - u[:, None] * self.edge, axis=1)
        i = int(np.argmin(gap))
        return i, float(self.s[i] + u[i] * self.length[i])

    def run(self, start: int, step: int, count: int) -> np.ndarray:
        """Vertex indices from ``start`` on, ``step`` = ±1, ``count`` of them."""
        return (start + step * np.arange(count)) % self.n


def _curvature(ring: _Ring, q: np.ndarray, window: float) -> float:
    """Signed curvature (1/mm) of the outline at ``q`` from the quartic fitted over ``window``."""
    i, s0 = ring.foot(q)
    sides = []
    for step, first in ((1, i + 1), (-1, i)):  # the vertices each side, up to a corner (the corner kept)
        run = ring.run(first, step, ring.n // 2)
        cut = np.nonzero(ring.corner[run])[0]
        run = run[: int(cut[0]) + 1] if len(cut) else run
        ds = np.abs(ring.s[run] - s0)
        sides.append((run, np.minimum(ds, ring.total - ds)))
    want = 2 * MIN_SIDE + 1
    picked = []
    for (run, ds), (other, _) in zip(sides, sides[::-1], strict=True):
        least = max(MIN_SIDE, want - len(other))  # a side cut short by a corner: the other gives more
        picked.append(run[: max(int(np.count_nonzero(ds <= window / 2)), least)])
    pts = ring.p[np.unique(np.concatenate(picked))]
    t = ring.edge[i] / ring.length[i]
    nrm = np.array([-t[1], t[0]])  # into the material
    origin = ring.p[i] + (s0 - ring.s[i]) * t
    x, y = (pts - origin) @ t, (pts - origin) @ nrm
    scale = float(np.max(np.abs(x)))
    if len(pts) < DEGREE + 2 or scale == 0:
        raise GeometryError(f"the outline has too few vertices ({len(pts)}) about {q.tolist()} to fit its curvature")
    c = np.polynomial.polynomial.polyfit(x / scale, y, DEGREE)
    d1, d2 = c[1] / scale, 2.0 * c[2] / scale**2
    return float(d2 / (1.0 + d1 * d1) ** 1.5)


def radius_of_curvature(outline, point, window: float, *, inside: bool = True) -> float:
    """Signed radius of curvature (mm) of the closed ``outline`` at ``point``: + convex, - concave
    (seen from the material: ``inside`` False for a ring's toothed hole). A quartic is fitted to
    the vertices within ``window`` mm of arc length centred on the point (module docstring).

    Examples
    --------
    >>> c = 5.0 * np.stack([np.cos(t := np.linspace(0, 2 * np.pi, 721)[:-1]), np.sin(t)], axis=1)
    >>> round(radius_of_curvature(c, (0.0, 5.0), 0.4, inside=False), 6)
    -5.0
    """
    window = check_number("window", window, 0.0, 1e6, low_open=True, unit="mm")
    k = _curvature(_Ring(_closed(outline, "outline", inside)), _point(point, "point"), window)
    return math.inf if k == 0.0 else 1.0 / k


def hertz_line_contact(force: float, width: float, rho1: float, rho2: float, e1: Elastic, e2: Elastic) -> HertzContact:
    """Hertz line contact of two flanks of signed radii ``rho1``, ``rho2`` (mm; convex +, concave -)
    under normal force ``force`` (N) over face width ``width`` (mm)."""
    force = check_number("force", force, 0.0, 1e9, unit="N")
    width = check_number("width", width, 0.0, 1e6, low_open=True, unit="mm")
    for name, rho in (("rho1", rho1), ("rho2", rho2)):
        if not isinstance(rho, int | float) or math.isnan(rho) or rho == 0:
            raise SpecError.out_of_range(name, rho, "a non-zero radius of curvature, mm (inf for a straight flank)")
    kappa = 1.0 / rho1 + 1.0 / rho2
    if kappa <= 0:
        raise GeometryError(
            f"the flanks do not touch in a line: 1/rho1 + 1/rho2 = {kappa:.6g} 1/mm must be > 0 (rho1 = {rho1:.6g} mm, "
            f"rho2 = {rho2:.6g} mm: the concave flank is tighter than the convex one)"
        )
    comp = e1.compliance + e2.compliance
    half = math.sqrt(4.0 * force * comp / (math.pi * width * kappa))
    return HertzContact(math.sqrt(force / (math.pi * width) * kappa / comp), half, 1 / kappa)


def _tooth(ring: _Ring, i: int, centre: np.ndarray, module: float, ring_gear: bool):
    """The tooth whose flank holds edge ``i``: its vertex indices from one space bottom over the tip
    to the other, and the bottoms' and the tip middle's points."""
    r = np.linalg.norm(ring.p - centre, axis=1) * (-1.0 if ring_gear else 1.0)  # height: up the tooth
    hyst, flat = 0.5 * module, 0.02 * module
    span = ring.n

    def extreme(seq, low: bool):
        h = -r[seq] if low else r[seq]
        best = np.maximum.accumulate(h)
        stop = np.nonzero(h < best - hyst)[0]
        end = int(stop[0]) if len(stop) else len(seq)
        top = np.nonzero(h[:end] >= best[end - 1] - flat)[0]
        return end, int(top[len(top) // 2]), int(top[-1])

    fwd, back = ring.run(i + 1, 1, span), ring.run(i, -1, span)
    up_fwd = r[fwd[min(3, span - 1)]] > r[back[min(3, span - 1)]]
    up, down = (fwd, back) if up_fwd else (back, fwd)
    _, b1, _ = extreme(down, True)
    _, _, tip_end = extreme(up, False)
    _, b2, _ = extreme(up[tip_end:], True)
    idx = np.concatenate([down[b1::-1], up[: tip_end + b2 + 1]])
    if len(set(idx.tolist())) != len(idx):
        raise GeometryError("no whole tooth found around the point: is the outline toothed, and the module right?")
    p1, p2 = ring.p[idx[0]], ring.p[idx[-1]]
    base = (p2 - p1) / np.linalg.norm(p2 - p1)
    up_n = np.array([-base[1], base[0]])
    height = (ring.p[idx] - p1) @ up_n
    if height[len(idx) // 2] < 0:
        up_n, height = -up_n, -height
    near = np.nonzero(height >= height.max() - flat)[0]
    s_idx = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(ring.p[idx], axis=0), axis=1))])
    mid_s = 0.5 * (s_idx[near[0]] + s_idx[near[-1]])
    j = min(int(np.searchsorted(s_idx, mid_s, side="right")) - 1, len(idx) - 2)
    f = (mid_s - s_idx[j]) / max(s_idx[j + 1] - s_idx[j], 1e-300)
    tip = ring.p[idx[j]] + f * (ring.p[idx[j + 1]] - ring.p[idx[j]])
    return idx, p1, p2, tip


def _tangent_point(pts: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    """The first point from ``pts[0]`` (a space bottom) up the fillet whose tangent makes ``angle``
    (rad) with ``axis``: edge directions belong to edge middles, interpolated in arc length."""
    e = np.diff(pts, axis=0)
    ln = np.linalg.norm(e, axis=1)
    psi = np.arccos(np.clip(np.abs(e @ axis) / ln, 0.0, 1.0))
    below = np.nonzero(psi <= angle)[0]
    if len(below) == 0 or below[0] == 0:
        raise GeometryError(
            f"no fillet point whose tangent makes {math.degrees(angle):.4g} deg with the tooth's centre line"
        )
    k = int(below[0])
    s = np.concatenate([[0.0], np.cumsum(ln)])
    mid_a, mid_b = s[k - 1] + ln[k - 1] / 2, s[k] + ln[k] / 2
    at = mid_a + (psi[k - 1] - angle) / (psi[k - 1] - psi[k]) * (mid_b - mid_a)
    j = min(int(np.searchsorted(s, at, side="right")) - 1, len(e) - 1)
    return pts[j] + (at - s[j]) / ln[j] * e[j]


def root_stress(
    outline,
    point,
    force: float,
    width: float,
    module: float,
    *,
    direction=None,
    centre=(0.0, 0.0),
    internal: bool = False,
    pressure_angle: float = 20.0,
    tangent_angle: float | None = None,
    window: float | None = None,
) -> RootStress:
    """Root bending stress of the tooth whose flank holds ``point`` (gear frame, mm), loaded by the
    normal force ``force`` (N) along ``direction`` (into the tooth; default the flank's normal),
    over face width ``width`` (mm); ``module`` (mm) and ``pressure_angle`` (degrees, α_n) refer Y_F
    to ISO's form; ``tangent_angle`` defaults to 30° (60° for a ring, ``internal``); ``window`` the
    arc (mm) the fillet radius is fitted over (default 0.1 module).

    Examples
    --------
    The module's: a rack-cut 19-tooth gear loaded at its tip.
    """
    force = check_number("force", force, 0.0, 1e9, unit="N")
    width = check_number("width", width, 0.0, 1e6, low_open=True, unit="mm")
    module = check_number("module", module, 0.0, 1e4, low_open=True, unit="mm")
    alpha_n = math.radians(check_number("pressure_angle", pressure_angle, 5.0, 45.0, unit="deg"))
    tangent = (60.0 if internal else 30.0) if tangent_angle is None else tangent_angle
    tangent = math.radians(check_number("tangent_angle", tangent, 5.0, 85.0, unit="deg"))
    window = 0.1 * module if window is None else check_number("window", window, 0.0, 1e6, low_open=True, unit="mm")
    ring = _Ring(_closed(outline, "outline", not internal))
    q, c = _point(point, "point"), _point(centre, "centre")
    i, _ = ring.foot(q)
    idx, b1, b2, tip = _tooth(ring, i, c, module, internal)
    root_mid = 0.5 * (b1 + b2)
    axis = (tip - root_mid) / np.linalg.norm(tip - root_mid)
    t_mid = int(np.argmin(np.linalg.norm(ring.p[idx] - tip, axis=1)))
    pa = _tangent_point(ring.p[idx[: t_mid + 1]], axis, tangent)
    pb = _tangent_point(ring.p[idx[t_mid:][::-1]], axis, tangent)
    where = int(np.nonzero(idx == i)[0][0]) if i in idx else int(np.nonzero(idx == (i + 1) % ring.n)[0][0])
    loaded, other = (pa, pb) if where < t_mid else (pb, pa)
    t = ring.edge[i] / ring.length[i]
    inward = np.array([-t[1], t[0]])
    d = inward if direction is None else _point(direction, "direction")
    d = d / np.linalg.norm(d)
    if d @ inward < 0:
        d = -d
    chord = other - loaded
    s_fn = float(np.linalg.norm(chord))
    mid = 0.5 * (loaded + other)
    cos_a = abs(float(d @ chord)) / s_fn
    if cos_a < 1e-9:
        raise GeometryError("the load line is normal to the critical section: no bending")
    lever = abs(float(_cross(q - mid, d)))
    h_f = lever / cos_a
    rho_f, rho_o = (abs(1.0 / _curvature(ring, p, window)) for p in (loaded, other))
    y_f = 6.0 * (h_f / module) * cos_a / ((s_fn / module) ** 2 * math.cos(alpha_n))
    big_l, q_s = s_fn / h_f, s_fn / (2.0 * rho_f)
    y_s = (1.2 + 0.13 * big_l) * q_s ** (1.0 / (1.21 + 2.3 / big_l))
    sigma_f = force * math.cos(alpha_n) / (width * module) * y_f * y_s
    comp = force * math.sqrt(max(1.0 - cos_a**2, 0.0)) / (width * s_fn)
    alpha_f = math.degrees(math.acos(min(cos_a, 1.0)))
    ends = np.array([loaded, other]), np.array([root_mid, tip])
    return RootStress(s_fn, h_f, alpha_f, rho_f, rho_o, y_f, y_s, sigma_f, comp, *ends)
