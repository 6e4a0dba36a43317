"""Teeth of non-circular external and internal gears as the envelope of a gear cutter.

The cutter is any :class:`~transplanter.cutter.Cutter`: a shaper cutter (below; external and
ring gears) or a rack cutter — the basic rack of a hob — whose reference line rolls on the
pitch curve (external gears without concave parts; its contact roll is closed-form too, see
:class:`~transplanter.cutter.RackCutter`). The cutter supplies the profile, its placement at a
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
loops and unions the spaces (:func:`_apart_spaces`, :func:`_space_polygons`; the tests hold the
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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import shapely
from scipy.spatial import cKDTree

from transplanter.backlash import resolve_backlash
from transplanter.cutter import Cutter, ShaperCutter
from transplanter.errors import GeometryError, SpecError, TransplanterError, check_int, check_number
from transplanter.interference import ScreenResult, pair_limits, screen_module, trimmed_addendum
from transplanter.pitch.arcframe import ArcFrame
from transplanter.pitch.curve import PitchCurve
from transplanter.pitch.periodic import Constant
from transplanter.tolerances import CHORD_TOLERANCE, SPIKE_LENGTH

__all__ = [
    "ArcFrame",
    "ToothSpace",
    "ToothedGear",
    "generate",
    "generate_pair",
    "per_gear",
    "secondary_cut",
]

#: the cap closing a tooth space on the free side, modules beyond its last samples outside the blank
CAP = 0.25

#: Ring tips are not trimmed below this addendum (modules): shorter teeth lose their contact
#: ratio, so the pair needs another remedy (cutter, tooth-count difference)
MIN_TRIMMED_ADDENDUM = 0.3


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


def _require_cutter(cutter) -> None:
    """SpecError unless ``cutter`` is a cutter with a module."""
    if not isinstance(cutter, Cutter):
        raise SpecError(f"cutter must be a cutter (ShaperCutter, RackCutter), got {type(cutter).__name__}")
    if cutter.module is None:
        raise SpecError("the cutter has no module: give it one (cutter.sized(m)), or leave it to a ToothedPairStudy")


def _on_gear(c, psi, q) -> np.ndarray:
    """Cutter-frame points ``q`` turned by ``psi`` about, and moved to, cutter centres ``c``
    (gear frame); the arrays broadcast, so one placement per point or an outer product both work."""
    cs, sn = np.cos(psi), np.sin(psi)
    return np.stack([c[..., 0] + cs * q[..., 0] - sn * q[..., 1], c[..., 1] + sn * q[..., 0] + cs * q[..., 1]], axis=-1)


def _tip_region(frame: ArcFrame, distance: float, tolerance: float, turns: int = 1) -> shapely.Geometry:
    """Region inside the pitch curve offset by ``distance`` along N (the tip curve)."""
    tip = shapely.Polygon(_offset(frame, distance, tolerance, turns))
    return tip if tip.is_valid else shapely.make_valid(tip, method="structure", keep_collapsed=False)


def _contact(frame, cutter: Cutter, tau, s_centres, side, shift):
    """Envelope points Y (spaces, n, 2) and contact rolls (spaces, n) of profile params ``tau``:
    the roll at which each profile point touches (``cutter.contact_rolls``), and the point
    placed there (``cutter.placement``)."""
    q, n, _ = cutter.profile(tau)
    sc = np.asarray(s_centres, dtype=float)[:, None]
    s = cutter.contact_rolls(frame, q, n, s_centres, side, shift)
    c, psi = cutter.placement(frame, s, sc, side, shift)
    return _on_gear(c, psi, q), s


def _chord_error(a, m, b):
    """Distance of points m from segments a-b (broadcast over leading axes)."""
    ab = b - a
    t = np.clip(np.einsum("...i,...i", m - a, ab) / np.maximum(np.einsum("...i,...i", ab, ab), 1e-300), 0, 1)
    return np.linalg.norm(m - (a + t[..., None] * ab), axis=-1)


def _symmetry(curve: PitchCurve, teeth: int) -> int:
    """How many times a gear of ``teeth`` on ``curve`` turns onto itself in a revolution: its
    tooth spaces repeat every ``1/turns`` of a turn. A circle's gear: every tooth; an n-lobed
    curve's: gcd(n, teeth) (a lobe's worth of teeth when the count is a multiple of the lobes)."""
    return teeth if isinstance(curve.radius, Constant) else math.gcd(curve.lobes, teeth)


def _turned(y: np.ndarray, turns: int) -> np.ndarray:
    """Envelopes ``y`` (spaces of one sector, samples, 2) turned onto all ``turns`` sectors, in
    order of arc length (a turn by 2π/turns advances the arc length by a sector)."""
    if turns == 1:
        return y
    a = 2 * math.pi * np.arange(turns) / turns
    cs, sn = np.cos(a)[:, None, None], np.sin(a)[:, None, None]
    x, v = y[None, ..., 0], y[None, ..., 1]
    return np.stack([cs * x - sn * v, sn * x + cs * v], axis=-1).reshape(-1, *y.shape[1:])


def _profile_grid(frame, cutter, s_centres, side, shift, tolerance):
    """Adaptive τ grid: every chord of every space within ``tolerance`` of the envelope."""
    counts = (3, 20, 6, 4, 6, 20, 3)
    tau = np.unique(np.concatenate([np.linspace(k, k + 1, c + 1) for k, c in enumerate(counts)]))
    y, _ = _contact(frame, cutter, tau, s_centres, side, shift)
    pending = np.ones(len(tau) - 1, dtype=bool)  # intervals whose chord is not yet known to fit
    for _ in range(20):
        idx = np.flatnonzero(pending)
        if not idx.size:
            break
        mid = 0.5 * (tau[idx] + tau[idx + 1])
        ym, _ = _contact(frame, cutter, mid, s_centres, side, shift)
        bad = _chord_error(y[:, idx], ym, y[:, idx + 1]).max(axis=0) > tolerance
        # insert the (already computed) midpoints where a chord strays; only their halves are
        # checked again (a chord that fits stays as it is)
        order = np.argsort(np.concatenate([tau, mid[bad]]), kind="stable")
        tau = np.concatenate([tau, mid[bad]])[order]
        y = np.concatenate([y, ym[:, bad]], axis=1)[:, order]
        new = np.flatnonzero(order >= len(order) - int(bad.sum()))
        pending = np.zeros(len(tau) - 1, dtype=bool)
        pending[new - 1] = pending[new] = True
    return tau, y


def _offset(frame: ArcFrame, distance: float, tolerance: float, turns: int = 1) -> np.ndarray:
    """Points of the pitch curve offset by ``distance`` along N (closed, first point not repeated);
    a curve that turns onto itself ``turns`` times is sampled on one sector, turned onto the rest."""
    n = max(256, int(math.ceil(frame.length / math.sqrt(8 * tolerance * 5.0))))
    n = -(-n // turns)  # per sector
    s = frame.length * np.arange(n) / (n * turns)
    p, _, nrm, _ = frame.at(s, curvature=False)
    return _turned((p + distance * nrm)[None], turns).reshape(-1, 2)


def _despike(points: np.ndarray, length: float) -> np.ndarray:
    """Drop vertices where the path turns back (> 90°) on a segment shorter than ``length``.

    Where two pieces of the envelope meet (flank and fillet) the sampled path can overshoot by
    a micrometre and come back: a zero-area spike that is a valid polygon but turns into a
    self-crossing once the DXF fits arcs through it.
    """
    pts = np.asarray(points, dtype=float)
    return pts[_despiked(pts, length)]


def _despiked(points: np.ndarray, length: float) -> np.ndarray:
    """Indices of the vertices :func:`_despike` keeps."""
    index = np.arange(len(points))
    while len(index) > 3:
        back = np.flatnonzero(_spikes(points[index], length)[1:-1]) + 1
        if back.size == 0:
            break
        index = np.delete(index, back[::2])  # every other one, then look again
    return index


def _spikes(points: np.ndarray, length: float) -> np.ndarray:
    """Mask of the vertices of paths ``points`` (..., n, 2) where the path turns back (> 90°)
    on a segment shorter than ``length`` (the ends are never spikes)."""
    u = points[..., 1:-1, :] - points[..., :-2, :]
    v = points[..., 2:, :] - points[..., 1:-1, :]
    uu, vv, uv = (np.einsum("...i,...i", a, b) for a, b in ((u, u), (v, v), (u, v)))
    inner = (np.minimum(uu, vv) < length * length) & (uv < 0)
    pad = np.zeros(points.shape[:-2] + (1,), dtype=bool)
    return np.concatenate([pad, inner, pad], axis=-1)


def _space_polygons(y, nrm, side, module):
    """Every tooth space as a polygon: its envelope closed 3 m out on the free side (along the
    normals ``nrm`` at the space centres), made valid where the envelope folds (undercut) — they
    overlap outside the blank, so they are unioned."""
    ext = 3.0 * module
    polys = []
    for j in range(y.shape[0]):
        out = side * nrm[j] * ext
        ring = np.concatenate([[y[j, 0] + out], _despike(y[j], SPIKE_LENGTH), [y[j, -1] + out]])
        poly = shapely.Polygon(ring)
        if not poly.is_valid:
            poly = shapely.make_valid(poly, method="structure", keep_collapsed=False)
        polys.append(poly)
    return polys


@dataclass(frozen=True)
class _Apart:
    """Tooth spaces that neither fold nor touch, as :func:`_apart_spaces` found them."""

    #: the spaces, one valid MultiPolygon
    spaces: shapely.MultiPolygon
    #: (spaces, samples) envelope samples that are vertices of the spaces' outlines
    kept: np.ndarray
    #: (spaces, 2) where each envelope enters and leaves the blank: arc length on the pitch curve
    crossings: np.ndarray


def _apart_spaces(y, in_blank, s_centres, nrm, frame, side, module, tip, offset, turns=1) -> _Apart | None:
    """The tooth spaces as one valid MultiPolygon without a union, or None.

    Each envelope is kept from the last sample before it enters the blank to the first after it
    leaves, and closed by a cap ``CAP`` m out on the free side (along the normals ``nrm`` at the
    space centres ``s_centres``). When every cap stays off the
    blank, no space folds (no undercut loop) and no two touch (a tooth between each pair), the
    spaces are already a valid MultiPolygon — the usual case, and a GEOS union of all spaces
    saved. Otherwise None: :func:`_space_polygons` and a union do it, as they always can.
    The crossings of the tip curve are found on one of the ``turns`` symmetric sectors.
    """
    if not isinstance(tip, shapely.Polygon) or tip.interiors or not in_blank.any(axis=1).all():
        return None
    n = y.shape[1]
    first = np.argmax(in_blank, axis=1) - 1
    last = n - np.argmax(in_blank[:, ::-1], axis=1)
    if first.min() < 0 or last.max() > n - 1:
        return None  # an envelope that starts or ends in the blank: the long closure is needed
    out = (side * CAP * module) * nrm
    rows = np.arange(y.shape[0])
    sample = np.arange(n)
    kept = (sample >= first[:, None]) & (sample <= last[:, None])
    spiky = _spikes(y, SPIKE_LENGTH) & kept
    spiky[rows, first] = spiky[rows, last] = False
    for j in np.flatnonzero(spiky.any(axis=1)):  # rare: drop the spikes of these spaces
        index = np.arange(first[j], last[j] + 1)
        kept[j] = False
        kept[j, index[_despiked(y[j, index], SPIKE_LENGTH)]] = True
    caps = np.stack([y[rows, last], y[rows, last] + out, y[rows, first] + out, y[rows, first]], axis=1)
    lines = shapely.linestrings(caps)
    if not (shapely.contains(tip, lines) if side < 0 else ~shapely.intersects(tip, lines)).all():
        return None
    # each ring: the kept samples in order, then the cap's two outer corners
    coords = np.concatenate([y, caps[:, 1:3]], axis=1)[np.concatenate([kept, np.ones((len(y), 2), bool)], axis=1)]
    owner = np.repeat(rows, kept.sum(axis=1) + 2)
    spaces = shapely.MultiPolygon(list(shapely.polygons(shapely.linearrings(coords, indices=owner))))
    if not spaces.is_valid:
        return None
    k = rows[: len(rows) // turns]
    outside = np.stack([y[k, first[k]], y[k, last[k]]], axis=1)
    inside = np.stack([y[k, first[k] + 1], y[k, last[k] - 1]], axis=1)
    crossings = _crossing(frame, outside, inside, s_centres[k, None], offset)
    sectors = frame.length / turns * np.arange(turns)
    return _Apart(spaces, kept, (crossings[None] + sectors[:, None, None]).reshape(-1, 2))


def _foot(frame, pts, s0, tol: float = 1e-12):
    """Arc length of the pitch-curve points nearest ``pts`` (..., 2), by Newton from ``s0`` (a
    few steps from within a tooth's length), and the points' heights along the outward normal
    there (mm)."""
    s = np.asarray(s0, dtype=float)
    for _ in range(20):
        p, t, nrm, kap = frame.at(s)
        r = pts - p
        step = np.einsum("...i,...i", r, t) / (1.0 + kap * np.einsum("...i,...i", r, nrm))
        s = s + step
        if np.max(np.abs(step)) < tol * frame.length:
            break
    p, _, nrm, _ = frame.at(s, curvature=False)
    return s, np.einsum("...i,...i", pts - p, nrm)


def _crossing(frame, outside, inside, s0, offset, iterations: int = 2):
    """Where the segments from ``outside`` to ``inside`` the blank (each (..., 2)) cross the tip
    curve (the pitch curve offset by ``offset`` along N): its arc length on the pitch curve,
    by regula falsi on the height above the tip curve (round-off in a few steps: the segments
    are one envelope sample long, where the height is nearly linear)."""
    a, b = outside, inside
    both, h = _foot(frame, np.stack([a, b]), np.stack([s0, s0]))
    (sa, sb), (ha, hb) = both, h - offset
    s = sa
    for _ in range(iterations):
        w = ha / np.where(ha == hb, 1.0, ha - hb)
        c = a + w[..., None] * (b - a)
        s, hc = _foot(frame, c, sa + w * (sb - sa))
        hc = hc - offset
        same = np.sign(hc) == np.sign(ha)
        a, sa, ha = np.where(same[..., None], c, a), np.where(same, s, sa), np.where(same, hc, ha)
        b, sb, hb = np.where(same[..., None], b, c), np.where(same, sb, s), np.where(same, hb, hc)
    return s


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
) -> ToothedGear:
    """Generate the teeth of a gear with pitch curve ``curve`` by the shaper ``cutter``.

    Parameters
    ----------
    curve : PitchCurve
        Its perimeter must be ``teeth * π * m`` (``GearPair.sized`` makes it so).
    cutter : Cutter
        A :class:`~transplanter.cutter.ShaperCutter` (external and ring gears) or a
        :class:`~transplanter.cutter.RackCutter` (external gears without concave parts).
    teeth : int
    internal : bool
        True for a ring gear (the cutter rolls inside the curve).
    shift : float
        Profile shift coefficient x (positive: cutter moved away from the gear material).
    addendum : float
        Gear addendum coefficient: the tip curve is ``(addendum + shift) m`` from the pitch
        curve on the free side.
    rim : float or None
        Ring gears: radial rim thickness beyond the deepest tooth space, mm (default 3 m).
    allow_undercut : bool
        If False, any undercut of the involute flank raises GeometryError.
    min_land : float
        Smallest tip land, in modules, before a tooth counts as pointed.
    tolerance : float
        Chord tolerance of the outline against the exact envelope, mm.
    phase : float
        Tooth-space centres at ``(j + phase) π m`` of arc length: 0 puts a space, 0.5 a tooth
        at the curve's start (a mating gear takes the other).
    """
    _require_cutter(cutter)
    if not isinstance(curve, PitchCurve):
        raise SpecError(f"curve must be a PitchCurve, got {type(curve).__name__}")
    m = cutter.module
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
    if abs(perimeter - teeth * math.pi * m) > 1e-9 * perimeter:
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
    pitch = frame.length / teeth
    s_centres = pitch * (np.arange(teeth) + phase)
    # the envelope of one symmetric sector, turned onto the others (a circle: one space)
    turns = _symmetry(curve, teeth)
    tau, y = _profile_grid(frame, cutter, s_centres[: teeth // turns], side, shift, tolerance)
    tip_offset = side * (addendum + shift) * m  # the tip curve: the pitch curve moved along N
    tip = _tip_region(frame, tip_offset, tolerance, turns)
    shapely.prepare(tip)
    inside_tip = shapely.contains_xy(tip, y[..., 0], y[..., 1])
    in_blank = np.tile(inside_tip if side > 0 else ~inside_tip, (turns, 1))
    y = _turned(y, turns)
    centres, _, normals, _ = frame.at(s_centres, curvature=False)
    apart = _apart_spaces(y, in_blank, s_centres, normals, frame, side, m, tip, tip_offset, turns)
    if apart is not None:
        cut, doubtful = apart.spaces, in_blank & ~apart.kept  # the kept samples are on the outline
    else:
        cut, doubtful = shapely.union_all(_space_polygons(y, normals, side, m)), in_blank
    if internal:
        depth = float(np.max(np.linalg.norm(y, axis=-1)))
        r_rim = depth + (3.0 * m if rim is None else float(rim))
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
        removed = (tip, cut)
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
        depth, where = secondary_cut(body, frame, cutter, teeth, shift, side, phase=phase, turns=turns)
        if depth > 4 * tolerance:
            tooth = int(round(where / pitch - phase)) % teeth
            raise GeometryError(
                f"secondary cutting near tooth space {tooth}: the cutter's other teeth reach {depth * 1000:.1f} µm "
                f"into the ring while leaving the mesh (limit {4 * tolerance * 1000:.1f} µm); use a cutter with "
                "fewer teeth or a larger ring"
            )
    if apart is not None:
        lands = _lands_between(frame, apart.crossings, tip_offset)
    else:
        lands = _tip_lands(tip, cut, frame, s_centres, side, (addendum + shift) * m, phase)
    thin = np.flatnonzero(lands < min_land * m)
    if thin.size:
        t = int(thin[0])
        raise GeometryError(
            f"pointed tooth {t}: its tip land is {lands[t]:.4g} mm, below min_land = {min_land:g} m = "
            f"{min_land * m:.4g} mm ({thin.size} teeth affected); reduce the addendum or the profile shift"
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


def secondary_cut(
    body,
    frame: ArcFrame,
    cutter: ShaperCutter,
    teeth: int,
    shift: float,
    side: float,
    per_pitch: int = 3,
    phase=0.0,
    turns: int = 1,
):
    """Deepest reach (mm) of any cutter position into the finished ``body``, and its roll (mm).

    Reaches below CHORD_TOLERANCE count as contact and give 0.

    The finished gear must not overlap the cutter at any roll position; where it does, the
    cutter's other teeth would have cut it (secondary cutting on ring gears, or interference).
    A gear that turns onto itself ``turns`` times a revolution (:func:`_symmetry`) is checked
    over one such sector: the others repeat it.
    """
    pitch = frame.length / teeth
    s = pitch * np.arange(teeth // turns * per_pitch) / per_pitch
    j = (np.round(s / pitch - phase) + phase) * pitch
    c, psi = cutter.placement(frame, s, j, side, shift)
    outline = cutter.outline(per_piece=6)
    whole = body
    if side < 0:  # ring: cutter points nearer the axis than the ring's innermost point are in free space
        reach = shapely.distance(shapely.Point(0.0, 0.0), body.interiors[0]) * (1 - 1e-9)
        # whole cutter teeth first: one whose bounding circle stays inside that radius is skipped
        teeth_q = outline.reshape(cutter.teeth, -1, 2)
        centre = teeth_q.mean(axis=1)
        radius = np.linalg.norm(teeth_q - centre[:, None], axis=-1).max(axis=1)
        far = np.linalg.norm(_on_gear(c[:, None, :], psi[:, None], centre), axis=-1) + radius[None] >= reach
        k, t = np.nonzero(far)
        placed = _on_gear(c[k, None, :], psi[k, None], teeth_q[t])  # (candidates, points, 2)
        xs, ys = placed[..., 0], placed[..., 1]
        near = np.hypot(xs, ys) >= reach
        margin = cutter.module
        if turns > 1 and near.any():  # one sector: the ring's teeth within a module of the cutter's
            x, y = xs[near], ys[near]
            box = (x.min() - margin, y.min() - margin, x.max() + margin, y.max() + margin)
            body = shapely.clip_by_rect(body, *box)
            if not body.is_valid:  # GEOS's fast clip may leave a dirty polygon: clip exactly then
                body = shapely.intersection(whole, shapely.box(*box))
        shapely.prepare(body)
        inside = np.zeros(xs.shape, dtype=bool)
        inside[near] = shapely.contains_xy(body, xs[near], ys[near])
    else:
        placed = _on_gear(c[:, None, :], psi[:, None], outline)
        xs, ys = placed[..., 0], placed[..., 1]
        k = np.arange(len(s))
        margin = math.inf
        shapely.prepare(body)
        inside = shapely.contains_xy(body, xs, ys)
    if not inside.any():
        return 0.0, 0.0
    row, i = np.nonzero(inside)
    pts = shapely.points(xs[row, i], ys[row, i])
    boundary = body.boundary
    shapely.prepare(boundary)
    deep = ~shapely.dwithin(boundary, pts, CHORD_TOLERANCE)  # the generating contact sits on the boundary
    if not deep.any():
        return 0.0, 0.0
    d = shapely.distance(boundary, pts[deep])
    if d.max() > margin / 2:  # deeper than the clipped edges are far: measure on the whole ring
        d = shapely.distance(whole.boundary, pts[deep])
    w = int(np.argmax(d))
    return float(d[w]), float(s[k[row[deep][w]]])


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


def per_gear(name: str, value) -> tuple[float, float]:
    """``value`` (one number for both gears, or a (driver, driven) pair) as a checked pair."""
    pair = value if isinstance(value, tuple | list) else (value, value)
    if len(pair) != 2:
        raise SpecError.out_of_range(name, value, "a number or a (driver, driven) pair of numbers")
    return (check_number(f"{name} (driver)", pair[0], -2.0, 2.0), check_number(f"{name} (driven)", pair[1], -2.0, 2.0))


def _cutter_remedy(pair, cutter: ShaperCutter, add, sh) -> str:
    """The shaper cutters (tooth counts) that would clear the closed-form limits with these
    addenda and still roll on both pitch curves — the 'cutter choice' remedy, in words."""
    r, p = (0, 1) if pair.ring == "driver" else (1, 0)
    frames = [ArcFrame.from_curve(c) for c in (pair.driver, pair.driven)]
    good = []
    for z in range(8, 61):
        try:
            other = replace(cutter, teeth=z)
            for k, frame in enumerate(frames):
                other.check_fits(frame, internal=k == r, shift=sh[k])
            lim = pair_limits(
                pair, other, ring_addendum=add[r], pinion_addendum=add[p], ring_shift=sh[r], pinion_shift=sh[p]
            )
        except TransplanterError:
            continue
        if not lim.problems():
            good.append(z)
    if not good:
        return "; no shaper cutter of 8 to 60 teeth clears it at these addenda"
    return (
        f"; cutters that clear it at these addenda: {good[0]} to {good[-1]} teeth"
        if good[-1] - good[0] + 1 == len(good)
        else f"; cutters that clear it at these addenda: {', '.join(map(str, good))} teeth"
    )


def generate_pair(
    pair,
    cutter: Cutter,
    teeth: tuple[int, int],
    *,
    backlash: float | None = None,
    addendum: float | tuple[float, float] = 1.0,
    shift: float | tuple[float, float] = 0.0,
    trim_ring_tips: bool = False,
    check_interference: bool = True,
    **kwargs,
) -> tuple[ToothedGear, ToothedGear]:
    """Both gears of a sized ``pitch.GearPair``: the driver with a space, the driven with a tooth at
    the start contact, so they mesh in the pair's start position.

    Parameters
    ----------
    backlash : float or None
        Circumferential backlash the pair is cut for, mm at the pitch point: each gear's teeth
        are thinned by half of it (the cutter is made ``backlash/2`` thicker). None: twice the
        cutter's own ``thickening`` if it has one, else the ISO/TR 10064-2 default
        (``backlash.design_backlash``). 0 only when zero backlash is really wanted.
    addendum, shift : float or (driver, driven)
        Addendum and profile-shift coefficients, for both gears or per gear.
    trim_ring_tips : bool
        Internal pairs are checked against the closed-form interference limits along the pitch
        curves (``interference.pair_limits``) *before* cutting. When the ring's tips reach into
        the pinion's fillet (or beyond the cutter's involute), True shortens the ring's
        addendum to the limit (less 0.02 m); False raises GeometryError naming the limit.
    check_interference : bool
        False cuts an interfering internal pair anyway (to study it: a finding), without raising.
    kwargs
        Go to :func:`generate` (``allow_undercut``, ``min_land``, ``rim``, ...).
    """
    ring = getattr(pair, "ring", None)
    add = list(per_gear("addendum", addendum))
    sh = per_gear("shift", shift)
    _require_cutter(cutter)
    j = resolve_backlash(backlash, cutter.thickening, cutter.module, pair.centre_distance, cutter.pressure_angle)
    cutter = replace(cutter, thickening=j / 2)
    if ring is not None:
        for k, curve in enumerate((pair.driver, pair.driven)):  # a cutter that cannot roll says so first
            cutter.check_fits(ArcFrame.from_curve(curve), internal=(k == 0) == (ring == "driver"), shift=sh[k])
        r, p = (0, 1) if ring == "driver" else (1, 0)
        names = ("ring", "planet")

        def limits():
            return pair_limits(
                pair, cutter, ring_addendum=add[r], pinion_addendum=add[p], ring_shift=sh[r], pinion_shift=sh[p]
            )

        lim = limits()
        if trim_ring_tips and lim.max_ring_addendum < add[r]:
            trimmed = trimmed_addendum(lim.max_ring_addendum)
            if trimmed > MIN_TRIMMED_ADDENDUM:
                add[r] = trimmed
                lim = limits()
            elif check_interference:
                raise GeometryError(
                    f"ring-tip trimming would leave an addendum of {trimmed:.2f} m (limit > {MIN_TRIMMED_ADDENDUM} m): "
                    + "; ".join(lim.problems(names, trochoid=False))
                )
        # KHK's trochoid limit, exact for circular gears, refuses non-circular pairs that mesh
        # (tests/test_screen.py): the cut teeth's meshing check judges tip fouling instead
        found = lim.problems(names, trochoid=False)
        if found and check_interference:
            raise GeometryError(
                "the internal pair interferes before cutting: "
                + "; ".join(found)
                + _cutter_remedy(pair, cutter, add, sh)
            )
    driver = generate(
        pair.driver, cutter, teeth[0], internal=ring == "driver", phase=0.0, addendum=add[0], shift=sh[0], **kwargs
    )
    driven = generate(
        pair.driven, cutter, teeth[1], internal=ring == "driven", phase=0.5, addendum=add[1], shift=sh[1], **kwargs
    )
    return driver, driven


def coarsest_cut(pair, *, max_module: float = 8.0, min_module: float = 0.5, **screen) -> ScreenResult | None:
    """The coarsest tooth count of an internal ``pair`` that passes the fouling screen
    (:func:`interference.screen_module`) *and* that the cutter can make: each screen result is
    cut as it will be shipped (:func:`generate_pair`, default backlash and chord tolerance —
    a trial at a coarser chord missed a 3 µm undercut); one the cutter refuses (undercut,
    secondary cutting, cutter fit) moves the search to the next finer tooth count. None if no
    module >= ``min_module`` passes both."""
    limit = max_module
    while True:
        found = screen_module(pair, max_module=limit, min_module=min_module, **screen)
        if found is None:
            return None
        sized, _ = pair.sized(teeth=found.teeth[0])
        try:
            generate_pair(
                sized,
                ShaperCutter(found.cutter_teeth, found.module),
                found.teeth,
                addendum=(found.ring_addendum, found.pinion_addendum)
                if pair.ring == "driver"
                else (found.pinion_addendum, found.ring_addendum),
                check_interference=False,
            )
        except GeometryError:
            limit = found.module * (1 - 1e-9)
            continue
        return found


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
            "away by the cutter tip (limit 0); use a profile shift, a cutter with fewer teeth (a shaper cutter "
            "instead of a rack) or allow_undercut=True"
        )
    return out


def _lands_between(frame, crossings, offset) -> np.ndarray:
    """Tip land of each tooth (tooth t between spaces t and t+1), mm, from where each space's
    envelope crosses the tip curve (``crossings``, (spaces, 2) arc lengths on the pitch curve):
    the shortest way along the tip curve from a crossing of space t to one of space t+1 (any
    other way crosses a space), its length ``∫ |1 + offset κ| ds`` by Simpson's rule (a land is
    shorter than a tooth, where κ hardly changes)."""
    length = frame.length
    ahead = np.roll(crossings, -1, axis=0)
    d = np.mod(ahead[:, None, :] - crossings[:, :, None], length).reshape(len(crossings), -1)
    back = length - d
    k = np.argmin(np.minimum(d, back), axis=1)
    rows = np.arange(len(crossings))
    start = crossings[rows, k // 2]
    step = np.where(d[rows, k] <= back[rows, k], d[rows, k], -back[rows, k])
    _, _, _, kap = frame.at(start[:, None] + step[:, None] * np.array([0.0, 0.5, 1.0]))
    f = np.abs(1.0 + offset * kap)
    return np.abs(step) * (f[:, 0] + 4 * f[:, 1] + f[:, 2]) / 6


def _tip_lands(tip, cut, frame, s_centres, side, offset, phase):
    """Length of tip curve left on each tooth, mm (tooth t between spaces t and t+1)."""
    left = shapely.difference(tip.exterior if isinstance(tip, shapely.Polygon) else tip.boundary, cut)
    pieces = getattr(left, "geoms", [left])
    lands = np.zeros(len(s_centres))
    pitch = frame.length / len(s_centres)
    probe_s = np.linspace(0, frame.length, 8 * len(s_centres), endpoint=False)
    p, _, nrm, _ = frame.at(probe_s, curvature=False)
    probe = p + side * offset * nrm
    for piece in pieces:
        if piece.is_empty or piece.length == 0:
            continue
        mid = np.asarray(piece.interpolate(0.5, normalized=True).coords)[0]
        k = int(np.argmin(np.linalg.norm(probe - mid, axis=1)))
        t = int(math.floor(probe_s[k] / pitch - phase)) % len(s_centres)
        lands[t] += piece.length
    return lands
