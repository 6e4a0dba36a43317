"""Involute rack cutter: the basic rack of a hob, whose reference line rolls on the pitch curve.

Straight flanks at the pressure angle, tip fillets and a tip land, over the same seven-piece
profile parameter as a shaper cutter's (:mod:`~transplanter.geometry.cutter_tooth`); its contact
roll is closed form even with a profile shift. It cuts external gears whose pitch curve has no
concave part, and refuses others by name. Importable from :mod:`transplanter.geometry.cutter`
too, beside the shaper.

Numpy only (``tests/test_layout.py``: one of the maths modules).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from transplanter.core.errors import GeometryError
from transplanter.geometry.cutter_tooth import _check_proportions, _Proportions, _whole_tooth

__all__ = ["RackCutter"]


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
