"""Teeth of non-circular external and internal gears as the envelope of a gear cutter.

The cutter is any :class:`~transplanter.geometry.cutter.Cutter`: a shaper cutter (below; external and
ring gears) or a rack cutter — the basic rack of a hob — whose reference line rolls on the
pitch curve (external gears without concave parts; its contact roll is closed-form too, see
:class:`~transplanter.geometry.rack_cutter.RackCutter`). The cutter supplies the profile, its placement at a
roll and the contact rolls; this module assembles the outline and runs the checks.

The cutter's pitch circle (radius ``r_c``) rolls without slip on the gear's pitch curve
(seed 004 eqs 11-18): at roll ``s`` (arc length along the pitch curve, body frame) the
pitch point is ``P(s)`` with unit tangent ``T`` and outward normal ``N``; the cutter centre is
``C = P + e (r_c + x m) N`` (``e = +1`` outside an external gear, ``-1`` inside a ring, ``x``
the profile shift: positive moves the cutter away from the gear material) and the cutter is
turned so that its body angle ``η_c(s) = -e (s - s_j)/r_c`` points at the pitch point, with
a cutter tooth centred there at ``s_j`` (the centre of tooth space j, ``s_j = j π m``).

**Meshing condition.** A cutter profile point ``q`` with normal ``n`` (``k = q × n``, normal
angle ``ν``) touches the envelope when its normal passes through the instantaneous centre of
the relative motion, which lies on the line C→P at distance
``λ(s) = (1 + e d κ) / (1/r_c + e κ)`` from C (``λ = r_c`` without shift). In the cutter frame
that is ``k = λ(s) sin(ν - η_c(s))``, so the contact roll is found in closed form
``s = s_j + e r_c (ν - asin(k/λ))`` (a few fixed-point steps when ``x != 0``) — no roll step,
so the flank accuracy is that of the pitch-curve frame (a quintic Hermite table in arc
length built from the exact curve, error < 1e-10 mm). The cutter profile is sampled
adaptively until every chord of the generated outline is within ``tolerance`` of the
envelope (0.25 µm by default).

The swept tooth space is the region bounded by the envelope, closed on the free side. The gear
is the blank (inside the tip curve, offset ``(h_a + x) m`` from the pitch curve to the free
side) minus the spaces; a ring is a rim disc minus the tip region and the spaces. Usually the
spaces neither fold nor touch: each envelope is then kept from just outside the blank to just
outside it again, closed by a short cap (``CAP`` m) on the free side, and all are subtracted at
once as one valid MultiPolygon — no union. Where an envelope folds (undercut), a cap would
reach the blank or two spaces touch (a nearly pointed tooth), the general path closes each
space 3 m out, lets shapely's ``make_valid(method="structure")`` take the union of a fold's
loops and unions the spaces (:mod:`transplanter.geometry.tooth_spaces`; the tests hold the
two to the same outline). A gear that turns onto itself — a circle's every tooth, an n-lobed
curve's every lobe (``gcd(n, z)`` sectors) — has its envelope, tip curve and checks computed on
one sector and turned onto the others. The brute-force Boolean subtraction of cutter positions
is the reference for tests and benchmarks (``tests/reference_teeth.py``), not part of the
library.

Checks, each naming the tooth and the limit: cutter radius against the smallest concave
(external) or convex (ring) radius of curvature, pitch-curve perimeter against ``z π m``,
undercut (involute flank removed by the fillet: depth reported), pointed teeth (tip land
below ``min_land``; the land measured on the exact tip curve between where the envelopes cross
it), teeth that fall apart.

The envelope's sampling is :mod:`~transplanter.geometry.envelope`'s, the secondary-cutting check
of ring gears :mod:`~transplanter.geometry.secondary_cutting`'s; this module assembles the gear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import cast

import numpy as np
import shapely
from scipy.spatial import cKDTree

from transplanter.core.errors import GeometryError, SpecError, check_int, check_number
from transplanter.core.forwarding import forward
from transplanter.core.tolerances import CHORD_TOLERANCE
from transplanter.geometry.cutter import Cutter, ShaperCutter
from transplanter.geometry.envelope import _profile_grid, _tip_region, _turned
from transplanter.geometry.pitch.arcframe import ArcFrame
from transplanter.geometry.pitch.curve import PitchCurve
from transplanter.geometry.pitch.periodic import Constant
from transplanter.geometry.proportions import RING_RIM
from transplanter.geometry.secondary_cutting import secondary_cut
from transplanter.geometry.tooth_spaces import apart_spaces, lands_between, space_polygons, tip_lands

__all__ = [
    "ArcFrame",
    "ToothSpace",
    "ToothedGear",
    "generate",
]

#: names this module gave before issue 41 moved them to modules of their own, still found here
__getattr__ = forward(
    __name__,
    {
        "SECTOR_RUN_OUT": "transplanter.geometry.secondary_cutting",
    },
)


@dataclass(frozen=True)
class ToothSpace:
    """One generated tooth space.

    Attributes
    ----------
    index : int
    s : float
        Roll position of its centre on the pitch curve, mm.
    pitch_point, normal : (2,) float
        Pitch-curve point and outward normal at ``s``.
    lower, upper : (n, 2) float
        Exact envelope points generated by the cutter's lower / upper involute flank, mm.
    undercut : float
        Largest depth of involute flank removed by undercut, mm (0 if none).
    """

    index: int
    s: float
    pitch_point: np.ndarray = field(repr=False)
    normal: np.ndarray = field(repr=False)
    lower: np.ndarray = field(repr=False)
    upper: np.ndarray = field(repr=False)
    undercut: float = 0.0


@dataclass(frozen=True, eq=False)
class ToothedGear:
    """A generated gear profile.

    Attributes
    ----------
    polygon : shapely.Polygon
        The gear body, mm. External: one outer toothed contour. Ring: the rim circle as the
        exterior and the toothed contour as its hole.
    teeth : int
    module : float
    internal : bool
    shift : float
        Profile shift coefficient x.
    spaces : tuple of ToothSpace
    tip_lands : (teeth,) float
        Length of tip curve left on each tooth (tooth t lies between spaces t and t+1), mm.
    blank, cut : shapely geometry
        What the teeth were cut from (inside the tip curve; a ring's rim disc) and what was cut
        away (the tooth spaces; a ring's tip region too): ``polygon = blank - cut``, up to
        specks. Solids repeat the subtraction in 3D; ``cut`` is put together from
        ``removed`` (the spaces, and a ring's tip region) when first asked for.
    """

    polygon: shapely.Polygon
    teeth: int
    module: float
    internal: bool
    shift: float
    cutter: Cutter
    spaces: tuple[ToothSpace, ...]
    tip_lands: np.ndarray = field(repr=False)
    blank: shapely.Geometry = field(repr=False, default=None)
    #: what was cut from the blank, in pieces that may overlap (their union is ``cut``)
    removed: tuple[shapely.Geometry, ...] = field(repr=False, default=())
    #: addendum coefficient the tips were cut to (modules)
    addendum: float = 1.0

    @cached_property
    def cut(self) -> shapely.Geometry:
        """Everything cut from the blank (the union of ``removed``)."""
        return self.removed[0] if len(self.removed) == 1 else shapely.union_all(self.removed)

    @property
    def toothed_contour(self) -> np.ndarray:
        """(n, 2) closed toothed contour (the exterior, or the ring's hole), mm."""
        ring = self.polygon.interiors[0] if self.internal else self.polygon.exterior
        return np.asarray(ring.coords)

    @property
    def undercut(self) -> float:
        return max((sp.undercut for sp in self.spaces), default=0.0)

    def nearest_space(self, point) -> int:
        """Index of the tooth space whose pitch point is nearest ``point`` (x, y)."""
        pp = np.array([sp.pitch_point for sp in self.spaces])
        return int(np.argmin(np.linalg.norm(pp - np.asarray(point, dtype=float), axis=1)))


def require_cutter(cutter) -> None:
    """SpecError unless ``cutter`` is a cutter with a module."""
    if not isinstance(cutter, Cutter):
        raise SpecError(f"cutter must be a cutter (ShaperCutter, RackCutter), got {type(cutter).__name__}")
    if cutter.module is None:
        raise SpecError("the cutter has no module: give it one (cutter.sized(m)), or leave it to a ToothedPairStudy")


def _symmetry(curve: PitchCurve, teeth: int) -> int:
    """How many times a gear of ``teeth`` on ``curve`` turns onto itself in a revolution: its
    tooth spaces repeat every ``1/turns`` of a turn. A circle's gear: every tooth; an n-lobed
    curve's: gcd(n, teeth) (a lobe's worth of teeth when the count is a multiple of the lobes)."""
    return teeth if isinstance(curve.radius, Constant) else math.gcd(curve.lobes, teeth)


def generate(
    curve: PitchCurve,
    cutter: Cutter,
    teeth: int,
    *,
    internal: bool = False,
    shift: float = 0.0,
    addendum: float = 1.0,
    rim: float | None = None,
    allow_undercut: bool = False,
    min_land: float = 0.2,
    tolerance: float = CHORD_TOLERANCE,
    phase: float = 0.0,
    spaces=None,
) -> ToothedGear:
    """Generate the teeth of a gear with pitch curve ``curve`` by the shaper ``cutter``.

    Parameters
    ----------
    curve : PitchCurve
        Its perimeter must be ``teeth * π * m`` (``GearPair.sized`` makes it so).
    cutter : Cutter
        A :class:`~transplanter.geometry.cutter.ShaperCutter` (external and ring gears) or a
        :class:`~transplanter.geometry.rack_cutter.RackCutter` (external gears without concave parts).
    teeth : int
    internal : bool
        True for a ring gear (the cutter rolls inside the curve).
    shift : float
        Profile shift coefficient x (positive: cutter moved away from the gear material).
    addendum : float
        Gear addendum coefficient: the tip curve is ``(addendum + shift) m`` from the pitch
        curve on the free side.
    rim : float or None
        Ring gears: radial rim thickness beyond the deepest tooth space, mm (default
        ``proportions.RING_RIM`` = 3 m).
    allow_undercut : bool
        If False, any undercut of the involute flank raises GeometryError.
    min_land : float
        Smallest tip land, in modules, before a tooth counts as pointed.
    tolerance : float
        Chord tolerance of the outline against the exact envelope, mm.
    phase : float
        Tooth-space centres at ``(j + phase) π m`` of arc length: 0 puts a space, 0.5 a tooth
        at the curve's start (a mating gear takes the other).
    spaces : array or None
        A **toothed sector** (incomplete gears, :mod:`transplanter.geometry.incomplete`): the arc lengths
        (mm, increasing, spanning less than a turn less 1.5 pitches) of the only tooth-space
        centres to cut, one circular pitch ``π m`` apart; the rest of the curve is left as the blank, so the
        perimeter need not be a whole number of teeth and ``teeth`` is the number of spaces.
    """
    require_cutter(cutter)
    if not isinstance(curve, PitchCurve):
        raise SpecError(f"curve must be a PitchCurve, got {type(curve).__name__}")
    m = cutter.module
    sector = spaces is not None
    if sector:
        spaces = np.asarray(spaces, dtype=float)
        if spaces.ndim != 1 or len(spaces) < 2 or np.any(np.diff(spaces) <= 0):
            raise SpecError("spaces must be two or more increasing arc lengths (mm) of tooth-space centres")
        teeth = len(spaces)
    else:
        check_int("teeth", teeth, 6, 100_000)
    shift = check_number("shift", shift, -1.5, 1.5)
    addendum = check_number("addendum", addendum, 0.0, 2.0, low_open=True, unit="m")
    if rim is not None:
        rim = check_number("rim", rim, 0.0, low_open=True, unit="mm")
    min_land = check_number("min_land", min_land, 0.0, 2.0, unit="m")
    # below 1e-6 mm the grid would outgrow memory before float round-off lets it converge
    tolerance = check_number("tolerance", tolerance, 1e-6, 0.1, unit="mm")
    phase = check_number("phase", phase, -1e6, 1e6)
    perimeter = curve.perimeter
    if sector and (spaces[-1] - spaces[0] > perimeter - 1.5 * math.pi * m):
        raise SpecError.out_of_range(
            "the toothed sector's span",
            float(spaces[-1] - spaces[0]),
            f"< the perimeter less one and a half pitches ({perimeter - 1.5 * math.pi * m:.6g} mm)",
        )
    if not sector and abs(perimeter - teeth * math.pi * m) > 1e-9 * perimeter:
        raise GeometryError(
            f"pitch-curve perimeter {perimeter:.9g} mm != teeth * π * m = {teeth * math.pi * m:.9g} mm "
            f"({teeth} teeth, m = {m:g}); size the pair with GearPair.sized(module=...) or (teeth=...)"
        )
    if addendum + shift >= cutter.dedendum:
        raise SpecError.out_of_range(
            "addendum + shift",
            addendum + shift,
            f"< the cutter's dedendum {cutter.dedendum} (its root would cut the tips)",
        )
    side = -1.0 if internal else 1.0
    frame = ArcFrame.from_curve(curve)
    cutter.check_fits(frame, internal, shift)
    pitch = math.pi * m if sector else frame.length / teeth
    s_centres = spaces if sector else pitch * (np.arange(teeth) + phase)
    # the envelope of one symmetric sector, turned onto the others (a circle: one space)
    turns = 1 if sector else _symmetry(curve, teeth)
    tau, y = _profile_grid(frame, cutter, s_centres[: teeth // turns], side, shift, tolerance)
    tip_offset = side * (addendum + shift) * m  # the tip curve: the pitch curve moved along N
    tip = _tip_region(frame, tip_offset, tolerance, turns)
    shapely.prepare(tip)
    inside_tip = shapely.contains_xy(tip, y[..., 0], y[..., 1])
    in_blank = np.tile(inside_tip if side > 0 else ~inside_tip, (turns, 1))
    y = _turned(y, turns)
    centres, _, normals, _ = frame.at(s_centres, curvature=False)
    apart = apart_spaces(y, in_blank, s_centres, normals, frame, side, m, tip, tip_offset, turns)
    if apart is not None:
        cut, doubtful = apart.spaces, in_blank & ~apart.kept  # the kept samples are on the outline
    else:
        cut, doubtful = shapely.union_all(space_polygons(y, normals, side, m)), in_blank
    if internal:
        depth = float(np.max(np.linalg.norm(y, axis=-1)))
        r_rim = depth + (RING_RIM * m if rim is None else float(rim))
        n_rim = max(720, int(math.ceil(2 * math.pi / math.acos(1 - tolerance / r_rim))))
        ang = 2 * math.pi * np.arange(n_rim) / n_rim
        rim_ring = np.stack([r_rim * np.cos(ang), r_rim * np.sin(ang)], axis=1)
        disc = shapely.Polygon(rim_ring)
        body = None
        if isinstance(tip, shapely.Polygon) and not tip.interiors:
            # cut inside a coarse rim (a 64-gon clear of the spaces: its inradius is past the
            # deepest space), then give the ring its fine rim: same toothed contour, fewer edges
            every = -(-n_rim // 64)
            if r_rim * math.cos(math.pi * every / n_rim) > depth:
                coarse = rim_ring[::every]
                cut_ring = shapely.difference(shapely.Polygon(coarse, [tip.exterior.coords]), cut)
                if isinstance(cut_ring, shapely.Polygon) and len(cut_ring.interiors) == 1:
                    body = shapely.Polygon(rim_ring, [cut_ring.interiors[0].coords])
        if body is None:
            body = shapely.difference(disc, shapely.union(tip, cut))
        removed: tuple[shapely.Geometry, ...] = (tip, cut)
    else:
        body = shapely.difference(tip, cut)
        removed = (cut,)
    body = _drop_specks(body, m)
    if not isinstance(body, shapely.Polygon) or body.is_empty:
        parts = len(getattr(body, "geoms", [])) if not body.is_empty else 0
        raise GeometryError(
            f"the teeth cut the gear apart ({parts} pieces): the tooth spaces meet below the tip; "
            "check the module, the cutter and the profile shift"
        )
    spaces = _tooth_spaces(body, doubtful, y, tau, s_centres, centres, normals, allow_undercut, tolerance)
    if internal:
        # a ring is cut by a shaper: a rack cannot roll inside a curve (cutter.check_fits refused it)
        shaper = cast(ShaperCutter, cutter)
        depth, where = secondary_cut(
            body, frame, shaper, teeth, shift, side, phase=phase, turns=turns, centres=s_centres if sector else None
        )
        if depth > 4 * tolerance:
            tooth = int(np.argmin(np.abs(s_centres - where))) if sector else int(round(where / pitch - phase)) % teeth
            raise GeometryError(
                f"secondary cutting near tooth space {tooth}: the cutter's other teeth reach {depth * 1000:.1f} µm "
                f"into the ring while leaving the mesh (limit {4 * tolerance * 1000:.1f} µm); use a cutter with "
                "fewer teeth or a larger ring"
            )
    if apart is not None:
        lands = lands_between(frame, apart.crossings, tip_offset)
    else:
        lands = tip_lands(tip, cut, frame, s_centres, side, (addendum + shift) * m, None if sector else phase)
    if sector:  # the "tooth" from the last space round to the first is the uncut rest of the blank
        lands[-1] = math.inf
    thin = np.flatnonzero(lands < min_land * m)
    if thin.size:
        t = int(thin[0])
        raise GeometryError(
            f"pointed tooth {t}: its tip land is {lands[t]:.4g} mm, below min_land = {min_land:g} m = "
            f"{min_land * m:.4g} mm ({thin.size} teeth affected); reduce the addendum (addendum=, --addendum) or "
            "the profile shift (shift=, --shift)"
        )
    return ToothedGear(
        body,
        int(teeth),
        m,
        internal,
        float(shift),
        cutter,
        tuple(spaces),
        lands,
        disc if internal else tip,
        removed,
        float(addendum),
    )


def _drop_specks(body, module: float):
    """Drop islands left where two tooth spaces almost meet (tooth tips cut off).

    Pieces smaller than 1e-3 m² cannot be machined and would be swept away; the pointed-tooth
    check then reports the tooth. Larger pieces are kept, so a gear that really falls apart
    is still reported.
    """
    if not isinstance(body, shapely.MultiPolygon):
        return body
    keep = [g for g in body.geoms if g.area >= 1e-3 * module**2]
    return keep[0] if len(keep) == 1 else shapely.MultiPolygon(keep)


def _near_boundary(boundary, pts: np.ndarray, distance: float) -> np.ndarray:
    """Mask of the points ``pts`` (n, 2) within ``distance`` of the prepared ``boundary``.

    Exactly ``shapely.dwithin``, faster: a point within ``distance`` of one of the boundary's
    vertices (scipy's cKDTree) is settled at once — most are, the envelope points being the
    outline's own vertices — and only the others go to GEOS.
    """
    near = np.zeros(len(pts), dtype=bool)
    if not len(pts):
        return near
    d, _ = cKDTree(shapely.get_coordinates(boundary)).query(pts, distance_upper_bound=distance)
    near[d <= distance] = True
    rest = np.flatnonzero(~near)
    if len(rest):
        near[rest] = shapely.dwithin(boundary, shapely.points(pts[rest]), distance)
    return near


def _tooth_spaces(body, doubtful, y, tau, s_centres, p, nrm, allow_undercut, tolerance):
    """Per-space metadata; undercut = involute envelope points inside the blank but cut away.

    ``doubtful`` (spaces, samples) marks the envelope samples inside the blank that may have been
    cut away: all of them after a union, none but the dropped spikes when the spaces are apart
    (their kept samples are vertices of the outline); ``p``, ``nrm``: the pitch points and
    normals at the space centres ``s_centres``."""
    flank = ((tau >= 1) & (tau <= 2)) | ((tau >= 5) & (tau <= 6))
    lower, upper = (tau >= 1) & (tau <= 2), (tau >= 5) & (tau <= 6)
    pts = y[:, flank].reshape(-1, 2)
    gone = doubtful[:, flank].reshape(-1)
    depth = np.zeros(len(pts))
    if gone.any():
        boundary = body.boundary
        shapely.prepare(boundary)
        gone[gone] = ~_near_boundary(boundary, pts[gone], 4 * tolerance)
        depth[gone] = shapely.distance(boundary, shapely.points(pts[gone]))
    depth = depth.reshape(y.shape[0], -1).max(axis=1)
    y_lower, y_upper = y[:, lower], y[:, upper]
    out = [
        ToothSpace(j, float(s_centres[j]), p[j], nrm[j], y_lower[j], y_upper[j], float(depth[j]))
        for j in range(y.shape[0])
    ]
    if not allow_undercut and depth.max() > 0:
        j = int(np.argmax(depth))
        raise GeometryError(
            f"undercut at tooth space {j}: {depth[j] * 1000:.1f} µm of involute flank is cut "
            "away by the cutter tip (limit 0); use a profile shift (shift=, --shift), a cutter with fewer teeth "
            "(a shaper cutter instead of a rack; --cutter-teeth) or allow_undercut=True (--allow-undercut)"
        )
    return out
