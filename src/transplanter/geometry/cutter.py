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

The :class:`Cutter` protocol and the tooth proportions every cutter shares are
:mod:`~transplanter.geometry.cutter_tooth`'s; the rack cutter is
:mod:`~transplanter.geometry.rack_cutter`'s. Both are importable from here, the cutters' one door.

Examples
--------
>>> import numpy as np
>>> from transplanter.geometry.cutter import ShaperCutter
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

import numpy as np
from scipy import optimize

from transplanter.core.errors import GeometryError, SpecError, check_int
from transplanter.geometry.cutter_tooth import Cutter, _check_proportions, _Proportions, _whole_tooth
from transplanter.geometry.rack_cutter import RackCutter

__all__ = ["Cutter", "ShaperCutter", "RackCutter", "involute"]


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
        :mod:`transplanter.geometry.teeth`)."""
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
