"""Involute pinion-type (gear-shaper) cutter: exact tooth profile with unit normals.

The cutter has ``teeth`` z_c, module m, pressure angle α; its pitch radius is
``r_c = m z_c / 2`` and base radius ``r_b = r_c cos α``. One cutter tooth, centred on the +x
axis of the cutter frame, is described by a single profile parameter τ running over seven
pieces, from the root of the lower flank, up the lower flank, over the tip, and down the
upper flank:

0. lower radial flank below the base circle (radial line from the root circle to r_b; real
   shaper cutters are radial there),
1. lower involute, from the base circle to the tip-fillet tangency,
2. lower tip fillet (radius ``tip_fillet * m``; 0 gives a sharp corner whose normal fans
   from the flank normal to the radial one — it then generates the trochoid root fillet),
3. tip land on the tip circle ``r_c + addendum * m``,
4. upper tip fillet, 5. upper involute, 6. upper radial flank.

Piece k covers τ ∈ [k, k+1]. For every τ the profile gives the point ``q`` (mm), the unit
normal ``n`` pointing out of the cutter material, and ``k = q × n``. Involute normals are
tangent to the base circle, so ``k = r_b`` on the whole involute: the tests use that as the
exactness check.

The tooth is ``π m / 2 + thickening`` thick on the pitch circle: ``thickening`` (mm) is the
backlash allowance the cutter removes from each generated gear's teeth.

Examples
--------
>>> import numpy as np
>>> from transplanter.cutter import ShaperCutter
>>> c = ShaperCutter(teeth=20, module=2.0)
>>> c.pitch_radius, round(c.base_radius, 6), c.tip_radius
(20.0, 18.793852, 22.5)
>>> q, n, k = c.profile(np.array([1.5, 5.5]))  # middle of each involute
>>> bool(np.allclose(np.abs(k), c.base_radius))  # lower flank: -r_b
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Protocol, runtime_checkable

import numpy as np
from scipy import optimize

from transplanter.errors import GeometryError, SpecError, check_int, check_number
from transplanter.proportions import CUTTER_ADDENDUM, CUTTER_DEDENDUM

__all__ = ["Cutter", "ShaperCutter", "RackCutter", "involute"]


@runtime_checkable
class Cutter(Protocol):
    """What the envelope (:mod:`transplanter.teeth`) needs from a generating tool.

    The tool's tooth, centred on the +x axis of its own frame and pointing at the gear, is one
    profile parameter τ ∈ [0, 7] over seven pieces (lower flank to tip to upper flank, as
    :class:`ShaperCutter` describes); ``profile`` gives points and outward unit normals;
    ``placement`` where its frame is when it has rolled to ``s`` on the pitch curve;
    ``contact_rolls`` the roll at which each profile point touches the envelope; ``check_fits``
    refuses a curve the tool cannot roll on. ``thickening`` is the backlash allowance, and
    ``addendum``/``dedendum`` (in modules) bound the gear's dedendum and addendum.
    """

    module: float
    pressure_angle: float
    addendum: float
    dedendum: float
    thickening: float

    def profile(self, tau): ...

    def placement(self, frame, s, s_centre, side: float, shift: float): ...

    def contact_rolls(self, frame, q, n, s_centres, side: float, shift: float) -> np.ndarray: ...

    def check_fits(self, frame, internal: bool, shift: float) -> None: ...

    def outline(self, per_piece: int = 24) -> np.ndarray: ...


@dataclass(frozen=True, kw_only=True)
class _Proportions:
    """A cutter's tooth proportions, shared by the shaper and the rack (keyword fields): pressure
    angle (rad); addendum, dedendum and tip fillet in modules; thickening in mm."""

    pressure_angle: float = math.radians(20.0)
    addendum: float = CUTTER_ADDENDUM
    dedendum: float = CUTTER_DEDENDUM
    tip_fillet: float = 0.2
    thickening: float = 0.0

    @property
    def m(self) -> float:
        """The module, mm, of a sized cutter (SpecError for one given without a module)."""
        module = getattr(self, "module", None)
        if module is None:
            raise SpecError(
                "the cutter has no module: give it one (cutter.sized(m)), or leave it to a ToothedPairStudy"
            )
        return module


def _check_proportions(cutter) -> bool:
    """Check a cutter's proportions (pressure angle; addendum, dedendum, tip fillet in modules)
    and, when it has one, its module and thickening (mm). False for a cutter without a module
    (sized later by its study), whose thickening must then be 0."""
    check_number("cutter pressure_angle", cutter.pressure_angle, math.radians(10), math.radians(35), unit="rad")
    # a cutter's addendum is the gear's dedendum (~1.25 m); past 2 m its tip outruns the involute
    check_number("cutter addendum", cutter.addendum, 0.5, 2.0, unit="m")
    check_number("cutter dedendum", cutter.dedendum, 0.0, 3.0, low_open=True, unit="m")
    check_number("cutter tip_fillet", cutter.tip_fillet, 0.0, 0.5, unit="m")
    if cutter.module is None:
        if cutter.thickening != 0:
            raise SpecError("a cutter's thickening (mm) needs its module: give both, or neither")
        return False
    m = check_number("cutter module", cutter.module, 0.01, 100.0, unit="mm")
    check_number("cutter thickening", cutter.thickening, -m / 2, m / 2, low_open=True, high_open=True, unit="mm")
    return True


def _whole_tooth(upper, tau):
    """A tooth's point q, outward normal n and k = q × n at profile parameters τ ∈ [0, 7], from
    its upper half ``upper(piece, t)`` (pieces 3..6, ``t`` from the tooth centre outwards): the
    lower pieces mirror the upper ones, piece p (t) <-> piece 6 - p (1 - t), and the tip land,
    piece 3, runs across the centre, so it is split at its middle."""
    tau = np.asarray(tau, dtype=float)
    if np.any((tau < 0) | (tau > 7)) or not np.all(np.isfinite(tau)):
        raise SpecError("profile parameter τ must lie in [0, 7]")
    piece = np.minimum(np.floor(tau), 6).astype(int)
    t = tau - piece
    lower = piece <= 2
    land = piece == 3
    up_piece = np.where(lower, 6 - piece, piece)
    up_t = np.where(land, np.abs(2 * t - 1), np.where(lower, 1 - t, t))
    q, n = upper(up_piece, up_t)
    flip = lower | (land & (t < 0.5))
    q[flip, 1] *= -1
    n[flip, 1] *= -1
    return q, n, q[..., 0] * n[..., 1] - q[..., 1] * n[..., 0]


def involute(angle):
    """inv α = tan α - α."""
    return np.tan(angle) - angle


@dataclass(frozen=True)
class ShaperCutter(_Proportions):
    """Involute shaper cutter.

    Parameters
    ----------
    teeth : int
        z_c (>= 6).
    module : float
        m, mm.
    pressure_angle : float
        α, rad (default 20°).
    addendum : float
        Cutter addendum coefficient (= generated gear's dedendum: 1 + clearance), default 1.25.
    dedendum : float
        Cutter dedendum coefficient (its root; must exceed the gear's addendum), default 1.35.
    tip_fillet : float
        Cutter tip radius coefficient (radius = tip_fillet * m), default 0.2; 0 = sharp.
    thickening : float
        Extra cutter tooth thickness on the pitch circle, mm (backlash allowance), default 0.
    """

    teeth: int
    module: float | None = None

    def __post_init__(self) -> None:
        check_int("cutter teeth", self.teeth, 6, 1000)
        if not _check_proportions(self):  # sized later, by the study that uses it (``sized``)
            return
        if self.root_radius <= 0:
            raise SpecError.out_of_range("cutter dedendum", self.dedendum, f"< z_c/2 = {self.teeth / 2}")
        self._geometry  # noqa: B018 - build and validate the tip now

    # -- circles ----------------------------------------------------------------------

    @property
    def pitch_radius(self) -> float:
        return self.m * self.teeth / 2

    @property
    def base_radius(self) -> float:
        return self.pitch_radius * math.cos(self.pressure_angle)

    @property
    def tip_radius(self) -> float:
        return self.pitch_radius + self.addendum * self.m

    @property
    def root_radius(self) -> float:
        return self.pitch_radius - self.dedendum * self.m

    @property
    def pitch(self) -> float:
        """Circular pitch π m, mm."""
        return math.pi * self.m

    @property
    def involute_end_roll(self) -> float:
        """Roll length (mm, along the line of action from the base circle) where the cutter's
        involute ends at its tip fillet: the point that generates a gear's *form circle*."""
        return self.base_radius * float(self._geometry["u_f"])

    def half_thickness_angle(self, radius) -> np.ndarray:
        """Half the tooth's angular thickness at ``radius`` >= r_b (rad)."""
        a = np.arccos(np.clip(self.base_radius / np.asarray(radius, dtype=float), -1, 1))
        psi = (self.pitch / 2 + self.thickening) / (2 * self.pitch_radius)
        return psi + involute(self.pressure_angle) - involute(a)

    # -- the upper half of the tooth: involute, fillet, tip ---------------------------

    def _upper_involute(self, u):
        """Point and outward normal of the upper involute at roll parameter u = tan α_ρ."""
        u = np.asarray(u, dtype=float)
        rho = self.base_radius * np.sqrt(1 + u * u)
        theta = self.half_thickness_angle(self.pitch_radius) + involute(self.pressure_angle) - (u - np.arctan(u))
        er = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
        et = np.stack([-np.sin(theta), np.cos(theta)], axis=-1)
        q = rho[..., None] * er
        n = (u[..., None] * er + et) / np.sqrt(1 + u * u)[..., None]
        return q, n

    @property
    def _geometry(self) -> dict:
        cached = self.__dict__.get("_geo")
        if cached is not None:
            return cached
        rb, ra, rf = self.base_radius, self.tip_radius, self.tip_fillet * self.m
        if ra <= rb:
            raise SpecError("cutter tip radius must exceed its base radius (addendum too small)")
        u_tip = math.sqrt((ra / rb) ** 2 - 1)
        if rf > 0:

            def gap(u: float) -> float:
                q, n = self._upper_involute(np.array(u))
                return float(np.linalg.norm(q - rf * n)) - (ra - rf)

            if gap(0.0) >= 0 or gap(u_tip) <= 0:
                raise GeometryError(
                    f"cutter tip_fillet = {self.tip_fillet} is too large: the fillet does not fit on the involute"
                )
            u_f = optimize.brentq(gap, 0.0, u_tip, xtol=1e-15)
            q_f, n_f = self._upper_involute(np.array(u_f))
            centre = q_f - rf * n_f
        else:
            u_f = u_tip
            q_f, n_f = self._upper_involute(np.array(u_f))
            centre = q_f
        a_flank = math.atan2(n_f[1], n_f[0])  # fillet normal angle at the flank tangency
        a_tip = math.atan2(centre[1], centre[0])  # radial direction at the tip-land tangency
        if a_flank < a_tip:
            a_flank += 2 * math.pi
        if a_tip <= 0:
            raise GeometryError(
                f"the cutter tooth is pointed: its tip land vanishes (tip radius {ra:.4g} mm, fillet {rf:.4g} mm)"
            )
        theta_b = float(self.half_thickness_angle(rb))
        geo = {
            "u_f": u_f,
            "centre": centre,
            "fillet": rf,
            "a_flank": a_flank,
            "a_tip": a_tip,
            "theta_b": theta_b,
            "rho_root": min(self.root_radius, rb),
        }
        object.__setattr__(self, "_geo", geo)
        return geo

    def _upper(self, piece: np.ndarray, t: np.ndarray):
        """Upper half (pieces 3..6 in τ); ``t`` in [0, 1] runs from the tooth centre outwards."""
        g = self._geometry
        q = np.empty(t.shape + (2,))
        n = np.empty(t.shape + (2,))
        # piece 3 (upper half of the tip land): angle 0 .. a_tip on the tip circle
        m = piece == 3
        ang = t[m] * g["a_tip"]
        n[m] = np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        q[m] = self.tip_radius * n[m]
        # piece 4: fillet, normal angle a_tip .. a_flank
        m = piece == 4
        ang = g["a_tip"] + t[m] * (g["a_flank"] - g["a_tip"])
        n[m] = np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        q[m] = g["centre"] + g["fillet"] * n[m]
        # piece 5: involute, u from u_f down to 0
        m = piece == 5
        q[m], n[m] = self._upper_involute((1 - t[m]) * g["u_f"])
        # piece 6: radial flank from r_b down to the root
        m = piece == 6
        rho = self.base_radius + t[m] * (g["rho_root"] - self.base_radius)
        th = g["theta_b"]
        q[m] = rho[:, None] * np.array([math.cos(th), math.sin(th)])
        n[m] = np.array([-math.sin(th), math.cos(th)])
        return q, n

    def profile(self, tau):
        """Point q (..., 2), outward unit normal n (..., 2) and k = q × n at profile parameters τ ∈ [0, 7]."""
        return _whole_tooth(self._upper, tau)

    # -- the envelope: where the cutter is at a roll, and which roll makes a point touch ---------

    def placement(self, frame, s, s_centre, side: float, shift: float):
        """Cutter-frame origin C (..., 2) and rotation ψ (...) at rolls ``s`` (mm of arc on
        ``frame``, a ``teeth.ArcFrame``) with a tooth centred at ``s_centre``: C on the normal at
        the pitch point, ``r_c + x m`` from it on the cutter's side (``side`` = +1 outside an
        external gear, -1 inside a ring), turned by ``η = -side (s - s_centre) / r_c``."""
        p, _, nrm, _ = frame.at(s, curvature=False)
        c = p + side * (self.pitch_radius + shift * self.m) * nrm
        u = -side * nrm
        eta = -side * (np.asarray(s, dtype=float) - s_centre) / self.pitch_radius
        return c, np.arctan2(u[..., 1], u[..., 0]) - eta

    def contact_rolls(self, frame, q, n, s_centres, side: float, shift: float) -> np.ndarray:
        """Rolls (spaces, points) at which profile points ``q`` with normals ``n`` touch the
        envelope of the spaces centred at ``s_centres``: ``k = λ sin(ν - η)`` in closed form,
        with a few fixed-point steps on λ when the cutter is shifted (module docstring of
        :mod:`transplanter.teeth`)."""
        k = q[..., 0] * n[..., 1] - q[..., 1] * n[..., 0]
        nu = np.arctan2(n[..., 1], n[..., 0])
        rc = self.pitch_radius
        d = rc + shift * self.m
        sc = np.asarray(s_centres, dtype=float)[:, None]
        lam = np.full((sc.shape[0], k.size), rc)
        for _ in range(40 if shift else 1):
            s = sc - side * rc * (nu - np.arcsin(np.clip(k / lam, -1.0, 1.0)))
            if not shift:
                break
            _, _, _, kap = frame.at(s)
            new = (1 + side * d * kap) / (1 / rc + side * kap)
            done = np.max(np.abs(new - lam)) < 1e-14 * rc
            lam = new
            if done:
                s = sc - side * rc * (nu - np.arcsin(np.clip(k / lam, -1.0, 1.0)))
                break
        return s

    def check_fits(self, frame, internal: bool, shift: float) -> None:
        """GeometryError if the cutter cannot roll on the curve: its rolling radius against the
        smallest concave (external gear) or convex (ring) radius of curvature."""
        d = self.pitch_radius + shift * self.m
        (s_lo, k_lo), (s_hi, k_hi) = frame.curvature_extremes
        if internal:
            limit, where, kind = (1 / k_hi if k_hi > 0 else math.inf), s_hi, "convex"
        else:
            limit, where, kind = (-1 / k_lo if k_lo < 0 else math.inf), s_lo, "concave"
        if d >= limit:
            raise GeometryError(
                f"cutter-curve interference: the cutter's rolling radius {d:.4g} mm (z_c = {self.teeth}, "
                f"m = {self.module:g}) exceeds the smallest {kind} radius of curvature {limit:.4g} mm of the pitch "
                f"curve at arc length {where:.2f} mm; use a cutter with fewer teeth or a smoother curve"
            )

    def sized(self, module: float) -> ShaperCutter:
        """This cutter at ``module`` (mm): a cutter stated without one takes its study's."""
        return replace(self, module=module)

    @property
    def label(self) -> str:
        return f"shaper cutter z0 = {self.teeth}"

    def outline(self, per_piece: int = 24) -> np.ndarray:
        """(n, 2) closed outline of the whole cutter (all teeth), mm, counter-clockwise."""
        tau = np.linspace(0, 7, 7 * per_piece + 1)
        q, _, _ = self.profile(tau)
        pts = []
        for j in range(self.teeth):
            a = 2 * math.pi * j / self.teeth
            c, s = math.cos(a), math.sin(a)
            pts.append(q @ np.array([[c, s], [-s, c]]))
        return np.concatenate(pts)


@dataclass(frozen=True)
class RackCutter(_Proportions):
    """Involute rack (the basic rack of a hob), for external gears.

    Its teeth have straight flanks at the pressure angle α, a tip land ``addendum · m`` from the
    reference line with fillets of radius ``tip_fillet · m``, and are ``π m / 2 + thickening``
    thick on the reference line. The reference line (offset by the profile shift ``x m``) rolls
    without slip on the pitch curve: at roll ``s`` the rack tooth centred at ``s_j`` has moved
    by ``s - s_j`` along the tangent. A profile point touches the envelope when its normal
    passes through the pitch point, so its roll is, in closed form,
    ``s = s_j - e (q_y - (q_x - x m) n_y / n_x)`` (rack frame: x towards the gear, y along the
    line) — no iteration even with a shift. A rack rolls on a straight line: it cuts only
    pitch curves without concave parts, and no ring gears.

    The profile parameter τ runs over the same seven pieces as a shaper cutter's: 0 the lower
    flank from the rack's root to the reference line, 1 on to the tip fillet, 2 the fillet,
    3 the tip land, 4-6 the upper side back to the root.

    Examples
    --------
    >>> r = RackCutter(2.0)
    >>> q, n = r.profile(np.array([1.5, 3.5]))[:2]
    >>> bool(np.allclose(n[0], [math.sin(r.pressure_angle), -math.cos(r.pressure_angle)])), q[1].tolist()
    (True, [2.5, 0.0])
    """

    module: float | None = None

    def __post_init__(self) -> None:
        if not _check_proportions(self):  # sized later, by the study that uses it (``sized``)
            return
        if self._geometry["tip_half"] <= 0:
            raise GeometryError(
                f"the rack tooth is pointed: its tip land vanishes (addendum {self.addendum} m, fillet "
                f"{self.tip_fillet} m, pressure angle {math.degrees(self.pressure_angle):.4g} deg)"
            )

    @property
    def pitch(self) -> float:
        """Circular pitch π m, mm."""
        return math.pi * self.m

    def sized(self, module: float) -> RackCutter:
        """This rack at ``module`` (mm): a rack stated without one takes its study's."""
        return replace(self, module=module)

    @property
    def label(self) -> str:
        return "rack cutter (hob)"

    @property
    def _geometry(self) -> dict:
        cached = self.__dict__.get("_geo")
        if cached is not None:
            return cached
        m, a = self.m, self.pressure_angle
        w0 = self.pitch / 4 + self.thickening / 2  # half thickness on the reference line
        rho = self.tip_fillet * m
        x_tip = self.addendum * m
        xc = x_tip - rho  # fillet centre: rho from the tip line and from the flank
        yc = (w0 * math.cos(a) - rho - xc * math.sin(a)) / math.cos(a)
        geo = {"w0": w0, "rho": rho, "x_tip": x_tip, "centre": np.array([xc, yc]), "tip_half": yc}
        geo["x_fillet"] = xc + rho * math.sin(a)  # where the flank meets the fillet
        object.__setattr__(self, "_geo", geo)
        return geo

    def _upper(self, piece: np.ndarray, t: np.ndarray):
        """Upper half (pieces 3..6); ``t`` in [0, 1] runs from the tooth centre outwards."""
        g, a = self._geometry, self.pressure_angle
        q = np.empty(t.shape + (2,))
        n = np.empty(t.shape + (2,))
        m = piece == 3  # tip land
        q[m] = np.stack([np.full(m.sum(), g["x_tip"]), t[m] * g["tip_half"]], axis=-1)
        n[m] = (1.0, 0.0)
        m = piece == 4  # fillet: normal angle 0 .. 90° - α
        ang = t[m] * (math.pi / 2 - a)
        n[m] = np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        q[m] = g["centre"] + g["rho"] * n[m]
        flank = np.array([math.sin(a), math.cos(a)])
        m = piece == 5  # flank from the fillet down to the reference line
        x = (1 - t[m]) * g["x_fillet"]
        q[m] = np.stack([x, g["w0"] - x * math.tan(a)], axis=-1)
        n[m] = flank
        m = piece == 6  # flank from the reference line to the rack's root
        x = -t[m] * self.dedendum * self.m
        q[m] = np.stack([x, g["w0"] - x * math.tan(a)], axis=-1)
        n[m] = flank
        return q, n

    def profile(self, tau):
        """Point q (..., 2) and outward unit normal n (..., 2) at τ ∈ [0, 7] (rack frame: x
        towards the gear, the reference line at x = 0), and k = q × n."""
        return _whole_tooth(self._upper, tau)

    def placement(self, frame, s, s_centre, side: float, shift: float):
        """Rack-frame origin (the tooth centre on the reference line) and rotation at rolls ``s``:
        moved ``s - s_centre`` back along the tangent and ``x m`` away from the gear."""
        p, t, nrm, _ = frame.at(s, curvature=False)
        u = -side * nrm  # towards the gear: the rack's +x
        c = p - (np.asarray(s, dtype=float) - s_centre)[..., None] * t - shift * self.m * u
        return c, np.arctan2(u[..., 1], u[..., 0])

    def contact_rolls(self, frame, q, n, s_centres, side: float, shift: float) -> np.ndarray:
        """Rolls at which profile points touch: their normal through the pitch point
        ``(x m, y)`` of the rack frame, ``y = q_y - (q_x - x m) n_y / n_x``, and ``s = s_j - e y``
        (the rack's +y is ``-e T``)."""
        y = q[..., 1] - (q[..., 0] - shift * self.m) * n[..., 1] / n[..., 0]
        return np.asarray(s_centres, dtype=float)[:, None] - side * y

    def check_fits(self, frame, internal: bool, shift: float) -> None:
        """A rack cuts external gears whose pitch curve has no concave part."""
        if internal:
            raise GeometryError("a rack cutter (hob) cannot cut a ring gear: use a shaper cutter")
        (s_lo, k_lo), _ = frame.curvature_extremes
        if k_lo < 0:
            raise GeometryError(
                f"a rack cutter (hob) rolls on a straight line and cannot cut the concave part of the pitch curve "
                f"at arc length {s_lo:.2f} mm (radius of curvature {-1 / k_lo:.4g} mm): use a shaper cutter"
            )

    def outline(self, per_piece: int = 24, teeth: int = 7) -> np.ndarray:
        """(n, 2) closed outline of a stretch of ``teeth`` rack teeth centred on the frame's
        x axis, closed by a back ``m`` behind the root line, counter-clockwise."""
        tau = np.linspace(0, 7, 7 * per_piece + 1)
        q, _, _ = self.profile(tau)
        q = q[::-1]  # from the upper root down the tooth to the lower root: clockwise in y for +x up
        half = (teeth - 1) / 2
        rows = [q + (0.0, (half - j) * self.pitch) for j in range(teeth)]
        back = -(self.dedendum + 1.0) * self.m
        top, bottom = rows[0][0, 1], rows[-1][-1, 1]
        pts = np.concatenate([[[back, top]], *rows, [[back, bottom]]])
        return pts[::-1] if _signed_area(pts) < 0 else pts


def _signed_area(pts: np.ndarray) -> float:
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
