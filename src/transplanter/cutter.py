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
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from transplanter.errors import GeometryError, SpecError, check_int, check_number

__all__ = ["ShaperCutter", "involute"]


def involute(angle):
    """inv α = tan α - α."""
    return np.tan(angle) - angle


@dataclass(frozen=True)
class ShaperCutter:
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
    module: float
    pressure_angle: float = math.radians(20.0)
    addendum: float = 1.25
    dedendum: float = 1.35
    tip_fillet: float = 0.2
    thickening: float = 0.0

    def __post_init__(self) -> None:
        check_int("cutter teeth", self.teeth, 6, 1000)
        check_number("cutter module", self.module, 0.01, 100.0, unit="mm")
        check_number("cutter pressure_angle", self.pressure_angle, math.radians(10), math.radians(35), unit="rad")
        # a cutter's addendum is the gear's dedendum (~1.25 m); past 2 m its tip outruns the involute
        check_number("cutter addendum", self.addendum, 0.5, 2.0, unit="m")
        check_number("cutter dedendum", self.dedendum, 0.0, 3.0, low_open=True, unit="m")
        check_number("cutter tip_fillet", self.tip_fillet, 0.0, 0.5, unit="m")
        m = float(self.module)
        check_number("cutter thickening", self.thickening, -m / 2, m / 2, low_open=True, high_open=True, unit="mm")
        if self.root_radius <= 0:
            raise SpecError.out_of_range("cutter dedendum", self.dedendum, f"< z_c/2 = {self.teeth / 2}")
        self._geometry  # noqa: B018 - build and validate the tip now

    # -- circles ----------------------------------------------------------------------

    @property
    def pitch_radius(self) -> float:
        return self.module * self.teeth / 2

    @property
    def base_radius(self) -> float:
        return self.pitch_radius * math.cos(self.pressure_angle)

    @property
    def tip_radius(self) -> float:
        return self.pitch_radius + self.addendum * self.module

    @property
    def root_radius(self) -> float:
        return self.pitch_radius - self.dedendum * self.module

    @property
    def pitch(self) -> float:
        """Circular pitch π m, mm."""
        return math.pi * self.module

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
        rb, ra, rf = self.base_radius, self.tip_radius, self.tip_fillet * self.module
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
        tau = np.asarray(tau, dtype=float)
        if np.any((tau < 0) | (tau > 7)) or not np.all(np.isfinite(tau)):
            raise SpecError("profile parameter τ must lie in [0, 7]")
        piece = np.minimum(np.floor(tau), 6).astype(int)
        t = tau - piece
        lower = piece <= 2
        # lower pieces mirror the upper ones: piece p (t) <-> piece 6 - p (1 - t); the tip land
        # piece 3 runs from -a_tip to +a_tip, so split it at its middle.
        up_piece = np.where(lower, 6 - piece, piece)
        up_t = np.where(lower, 1 - t, t)
        land = piece == 3
        up_t = np.where(land, np.abs(2 * t - 1), up_t)
        q, n = self._upper(up_piece, up_t)
        flip = lower | (land & (t < 0.5))
        q[flip, 1] *= -1
        n[flip, 1] *= -1
        k = q[..., 0] * n[..., 1] - q[..., 1] * n[..., 0]
        return q, n, k

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
