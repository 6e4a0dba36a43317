"""The load at a contact of two made gears and its stresses: ``F = |T|/ℓ``, ℓ the lever arm of the
common normal about the loaded gear's centre; both flanks' local radii there and the Hertz stress;
the root stress of each gear's tooth whose flank holds the contact point
(:mod:`~transplanter.proof.tooth_stress` measures them on the outlines); and the safety factors
against a catalogued gear material (:mod:`transplanter.shop.catalogue.gear_materials`).

The contact itself (point, common normal, which gears and where they are) comes from the meshing
proof (:mod:`~transplanter.proof.meshing`) or the machine's posed chain; this module rates it. Its
last section prepares a posed pair for :mod:`~transplanter.proof.mesh_cycle`, which closes the
loaded flanks (the smallest turn of the loaded gear at which the outlines touch, in closed form by
:mod:`transplanter.geometry.contact`) and finds the contacts there.

Examples
--------
>>> from transplanter.shop.catalogue.gear_materials import gear_material
>>> s = safety_factors(1000.0, 215.0, gear_material("18CrNiMo7-6"))
>>> round(s.s_h, 3), round(s.s_f, 3)
(1.5, 4.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from transplanter.core.errors import GeometryError, SpecError, check_number
from transplanter.geometry import contact
from transplanter.proof.tooth_stress import (
    CORNER_DEG,
    STEEL,
    Elastic,
    HertzContact,
    RootStress,
    _cross,
    _point,
    hertz_line_contact,
    radius_of_curvature,
    root_stress,
)

__all__ = ["MeshContactLoad", "SafetyFactors", "mesh_contact_load", "safety_factors"]


@dataclass(frozen=True)
class MeshContactLoad:
    """Load and stresses at one contact of a pair: normal force ``force`` (N), the lever arm of
    the normal about the loaded gear's centre (mm), both flanks' signed radii (mm), Hertz and the
    root stress of each gear's loaded tooth. ``hertz`` is None where a radius is None: a corner of
    one outline on the other's flank (an edge contact, where Hertz does not hold)."""

    force: float
    lever_arm: float
    radii: tuple[float | None, float | None]
    hertz: HertzContact | None
    root: tuple[RootStress, RootStress]


@dataclass(frozen=True)
class SafetyFactors:
    """S_H = σ_Hlim/σ_H and S_F = σ_FE/σ_F against ``material`` (its ``source`` cited)."""

    s_h: float
    s_f: float
    material: object


def _pose(pose, name: str) -> tuple[np.ndarray, float]:
    try:
        centre, angle = pose
    except (TypeError, ValueError) as exc:
        raise SpecError(f"{name} must be (centre (x, y) mm, angle rad) of the gear frame in the machine") from exc
    return _point(centre, f"{name} centre"), check_number(f"{name} angle", angle, -1e6, 1e6, unit="rad")


def mesh_contact_load(
    outlines,
    poses,
    point,
    normal,
    torque: float,
    *,
    loaded: int = 0,
    width: float,
    module: float,
    elastic: tuple[Elastic, Elastic] = (STEEL, STEEL),
    internal: tuple[bool, bool] = (False, False),
    pressure_angle: float = 20.0,
    window: float | None = None,
    radii: tuple[float | None, float | None] = (None, None),
) -> MeshContactLoad:
    """Load and stresses at a contact of two made gears.

    Parameters
    ----------
    outlines : two (n, 2) arrays
        Each gear's toothed contour in its own frame, mm (a ring's hole contour with ``internal``).
    poses : two (centre, angle)
        Where each gear frame is in the machine: ``x_machine = centre + R(angle) x_gear`` (mm, rad).
    point, normal : (2,)
        The contact point and the common normal, machine frame.
    torque : float
        Torque on gear ``loaded`` (0 or 1) about its centre, N mm.
    width, module, pressure_angle, window
        Face width (mm), module (mm), α_n (degrees) for Y_F, the radius fit's arc (default 0.1 m).
    elastic : two Elastic
    radii : two float or None
        Each flank's signed radius (mm): None to measure it at ``point`` (the default); a number
        measured elsewhere (at the end of a flank that ends in a corner at the contact); NaN for a
        corner that pokes the other flank (an edge contact): the radius is then None, and so is Hertz.
    """
    if len(outlines) != 2 or len(poses) != 2:
        raise SpecError("outlines and poses must each be given for the two gears")
    if loaded not in (0, 1):
        raise SpecError.out_of_range("loaded", loaded, "0 or 1 (the gear the torque acts on)")
    torque = check_number("torque", torque, -1e12, 1e12, unit="N mm")
    module = check_number("module", module, 0.0, 1e4, low_open=True, unit="mm")
    window = 0.1 * module if window is None else window
    p, n = _point(point, "point"), _point(normal, "normal")
    if np.linalg.norm(n) == 0:
        raise SpecError("normal must be a non-zero direction")
    n = n / np.linalg.norm(n)
    placed = [_pose(pose, f"poses[{k}]") for k, pose in enumerate(poses)]
    lever = abs(float(_cross(p - placed[loaded][0], n)))
    if lever < 1e-9 * max(1.0, float(np.linalg.norm(p - placed[loaded][0]))):
        raise GeometryError(f"the contact normal passes through gear {loaded}'s centre: it carries no torque there")
    force = abs(torque) / lever
    given, radii, roots = radii, [], []
    for k in range(2):
        c, ang = placed[k]
        rot = np.array([[math.cos(ang), math.sin(ang)], [-math.sin(ang), math.cos(ang)]])  # machine -> gear
        q, d = rot @ (p - c), rot @ n
        if given[k] is None:
            radii.append(radius_of_curvature(outlines[k], q, window, inside=not internal[k]))
        else:
            radii.append(None if math.isnan(given[k]) else float(given[k]))
        kw = {"direction": d, "internal": internal[k], "pressure_angle": pressure_angle, "window": window}
        roots.append(root_stress(outlines[k], q, force, width, module, **kw))
    hertz = None if None in radii else hertz_line_contact(force, width, radii[0], radii[1], elastic[0], elastic[1])
    return MeshContactLoad(force, lever, (radii[0], radii[1]), hertz, (roots[0], roots[1]))


def safety_factors(sigma_h: float, sigma_f: float, material) -> SafetyFactors:
    """S_H = σ_Hlim/σ_H and S_F = σ_FE/σ_F (σ_FE = Y_ST σ_Flim, Y_ST = 2) against a catalogue
    gear material (:func:`transplanter.shop.catalogue.gear_materials.gear_material`), with every
    life, lubrication, roughness, size and load factor of ISO 6336 taken as 1: the nominal figures
    a designer compares first.

    """
    sigma_h = check_number("sigma_h", sigma_h, 0.0, 1e7, low_open=True, unit="MPa")
    sigma_f = check_number("sigma_f", sigma_f, 0.0, 1e7, low_open=True, unit="MPa")
    return SafetyFactors(material.sigma_hlim / sigma_h, material.sigma_fe / sigma_f, material)


# -- closing the loaded flanks of a posed pair (what :mod:`~transplanter.proof.mesh_cycle` rates) --------------------


def _outline(value, name: str, ring: bool) -> np.ndarray:
    """A closed outline (no closing repeat), turned so the material is on its left: a body's
    counter-clockwise, a ring's hole clockwise. The outward normal of edge i is then (t_y, -t_x)."""
    p = np.asarray(value, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 4 or not np.all(np.isfinite(p)):
        raise SpecError(f"{name} must be a finite (n, 2) array of at least 4 points, mm")
    if np.allclose(p[0], p[-1]):
        p = p[:-1]
    area = float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
    return p if (area > 0) != ring else p[::-1].copy()


def _foot(p, ps, pe):
    d = pe - ps
    t = np.clip(np.einsum("ij,ij->i", p - ps, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    return ps + t[:, None] * d


class _Gear:
    """One outline prepared: its vertices (material on the left), convex corners, arc length,
    a k-d tree of its vertices."""

    def __init__(self, xy: np.ndarray, ring: bool):
        self.xy, self.ring = xy, ring
        self.corners = _convex_corners(xy)
        edge = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
        self.longest = float(edge.max())
        self.s = np.concatenate(([0.0], np.cumsum(edge)))
        self.tree = cKDTree(xy)

    def piece(self, q: np.ndarray, span: float) -> np.ndarray:
        """The outline within ``span`` of arc length of its vertex nearest ``q`` (gear frame), closed
        through two points towards the gear centre (half the least radius), so that it bounds
        the same side as the whole outline: what the tooth of ``q`` and its neighbours' spaces
        need, at a fraction of the whole outline's cost."""
        total = float(self.s[-1])
        if 2 * span >= total:
            return self.xy
        _, i = self.tree.query(q)
        ds = (self.s[:-1] - self.s[i] + total / 2) % total - total / 2
        idx = np.nonzero(np.abs(ds) <= span)[0]
        idx = idx[np.argsort(ds[idx])]
        ends = self.xy[idx[[-1, 0]]]
        inner = 0.5 * float(np.hypot(*self.xy.T).min()) * ends / np.hypot(*ends.T)[:, None]
        return np.concatenate((self.xy[idx], inner))


class _Closing:
    """The vertex/edge pairs of one chunk of positions, in frames centred on gear 1's centre with
    the machine's orientation, gear 1 at its design angle."""

    def __init__(self, gear0: _Gear, gear1: _Gear, ring0, c0, a0, c1, a1, tol, limit):
        g0, g1 = gear0.xy, gear1.xy
        n0, n1, k = len(g0), len(g1), len(c1)
        r1 = np.hypot(g1[:, 0], g1[:, 1])
        pad = tol + limit * float(r1.max()) + 1e-9
        # gear 0's vertices in gear 1's radius band, gear 1's in gear 0's
        rel0 = c0 - c1  # gear 0's centre about gear 1's
        s0, i0 = self._select(gear0, a0, -rel0, float(r1.min()) - pad, float(r1.max()) + pad)
        band0 = np.hypot(g0[:, 0], g0[:, 1])
        lo, hi = (float(band0.min()) - pad, math.inf) if ring0 else (0.0, float(band0.max()) + pad)
        s1, i1 = self._select(gear1, a1, rel0, lo, hi)
        self.k, self.n0, self.n1 = k, n0, n1
        self.q0 = contact.rotate(g0[i0], a0, s0) + rel0[s0]
        self.e0 = contact.rotate(g0[(i0 + 1) % n0], a0, s0) + rel0[s0]
        self.p1 = contact.rotate(g1[i1], a1, s1)
        self.e1 = contact.rotate(g1[(i1 + 1) % n1], a1, s1)
        self.s0, self.i0, self.s1, self.i1 = s0, i0, s1, i1
        long0, long1 = gear0.longest, gear1.longest
        lim = np.full(k, limit)
        # (a) a vertex of gear 1 meets an edge of gear 0; (b) a vertex of gear 0 an edge of gear 1
        va, ea = contact.pairs(self.p1, s1, self.q0, self.e0, s0, tol)
        self.va, self.ea = contact.within(self.p1, va, self.q0, ea, lim[s0[ea]], long0 + tol)
        vb, eb = contact.pairs(self.q0, s0, self.p1, self.e1, s1, tol)
        self.vb, self.eb = contact.within(self.q0, vb, self.p1, eb, lim[s1[eb]], long1 + tol)

    @staticmethod
    def _select(gear: _Gear, angle, centre, lo, hi):
        """(step, vertex) of the vertices of ``gear`` (turned by ``angle`` per step) whose distance
        from ``centre`` (per step, about the gear's own centre, machine orientation) lies in
        [lo, hi], with the vertex before each (every edge reaching the band)."""
        c, s = np.cos(angle), np.sin(angle)
        own = np.column_stack((c * centre[:, 0] + s * centre[:, 1], -s * centre[:, 0] + c * centre[:, 1]))
        n = len(gear.xy)
        if math.isfinite(hi):
            found = gear.tree.query_ball_point(own, hi)
            count = np.fromiter((len(f) for f in found), dtype=int, count=len(found))
            step = np.repeat(np.arange(len(own)), count)
            idx = np.concatenate(found).astype(int) if count.sum() else np.zeros(0, dtype=int)
        else:
            step, idx = np.repeat(np.arange(len(own)), n), np.tile(np.arange(n), len(own))
        d = np.hypot(*(gear.xy[idx] - own[step]).T)
        keep = (d >= lo) & (d <= hi)
        key = np.unique(np.concatenate((step[keep] * n + idx[keep], step[keep] * n + (idx[keep] - 1) % n)))
        return key // n, key % n

    def first_contact(self, sense: np.ndarray, limit: float) -> np.ndarray:
        """The smallest turn of gear 1 in ``sense`` (±1 per step) at which the outlines touch."""
        xa, oka = contact.crossings(self.p1[self.va], self.q0[self.ea], self.e0[self.ea])
        da = contact.angle_between(self.p1[self.va], xa)
        sa = np.broadcast_to(self.s1[self.va], da.shape)
        xb, okb = contact.crossings(self.q0[self.vb], self.p1[self.eb], self.e1[self.eb])
        db = -contact.angle_between(self.q0[self.vb], xb)
        sb = np.broadcast_to(self.s0[self.vb], db.shape)
        turn = np.concatenate((da[oka], db[okb]))
        step = np.concatenate((sa[oka], sb[okb]))
        signed = turn * sense[step]
        ok = (signed >= 0.0) & (signed <= limit)
        best = np.full(self.k, np.inf)
        np.minimum.at(best, step[ok], signed[ok])
        return best * sense

    def touching(self, turn: np.ndarray, tol: float) -> dict:
        """Every vertex/edge pair within ``tol`` with gear 1 turned by ``turn``, as arrays: ``step``,
        gear 1's boundary index ``at``, ``gap``, the points ``on1`` and ``on0`` (mm, about gear 1's
        centre), ``which`` (0: a vertex of gear 1 on an edge of gear 0, 1: the other way), the
        touching ``vertex`` and the edge's ``first`` vertex (outline indices), the edge direction
        ``tangent`` (as turned), the foot's distances ``ends`` (2, m) from the edge's two ends."""
        pa = contact.rotate(self.p1[self.va], turn, self.s1[self.va])
        q0, e0 = self.q0[self.ea], self.e0[self.ea]
        fa = _foot(pa, q0, e0)
        ps = contact.rotate(self.p1[self.eb], turn, self.s1[self.eb])
        pe = contact.rotate(self.e1[self.eb], turn, self.s1[self.eb])
        vb = self.q0[self.vb]
        fb = _foot(vb, ps, pe)
        a, b = np.hypot(*(pa - fa).T) <= tol, np.hypot(*(vb - fb).T) <= tol

        def both(x, y):
            return np.concatenate((x[a], y[b]))

        return {
            "step": both(self.s1[self.va], self.s1[self.eb]),
            "at": both(self.i1[self.va], self.i1[self.eb]),
            "gap": both(np.hypot(*(pa - fa).T), np.hypot(*(vb - fb).T)),
            "on1": both(pa, fb),
            "on0": both(fa, vb),
            "which": both(np.zeros(len(pa), int), np.ones(len(vb), int)),
            "vertex": both(self.i1[self.va], self.i0[self.vb]),
            "first": both(self.i0[self.ea], self.i1[self.eb]),
            "tangent": both(e0 - q0, pe - ps),
            "ends": np.stack(
                (
                    both(np.hypot(*(fa - q0).T), np.hypot(*(fb - ps).T)),
                    both(np.hypot(*(fa - e0).T), np.hypot(*(fb - pe).T)),
                )
            ),
        }


def _convex_corners(g: np.ndarray) -> np.ndarray:
    """Mask of the vertices where the outline (material on its left) turns left by more than
    ``CORNER_DEG``: corners that stick out of the material."""
    t = np.roll(g, -1, axis=0) - g
    back = np.roll(t, 1, axis=0)
    turn = np.arctan2(back[:, 0] * t[:, 1] - back[:, 1] * t[:, 0], np.einsum("ij,ij->i", back, t))
    return turn > math.radians(CORNER_DEG)
