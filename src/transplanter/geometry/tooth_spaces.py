"""Tooth spaces swept by the cutter, as polygons, and the tip lands they leave.

The envelope samples of every tooth space (``teeth.generate``) become the region the cutter
removes. Usually the spaces neither fold nor touch: each envelope is then kept from just outside
the blank to just outside it again, closed by a short cap (``CAP`` m) on the free side, and all
are subtracted at once as one valid MultiPolygon (:func:`apart_spaces`). Otherwise every space is
closed 3 m out and made valid where it folds (:func:`space_polygons`), and the spaces are unioned.
The tip land of each tooth is measured on the exact tip curve between where the envelopes cross
it (:func:`lands_between`), or on the cut tip curve (:func:`tip_lands`) after a union.

Numpy and shapely only; no cutter, no pitch-curve type (a frame is anything with ``length`` and
``at(s)``, see :class:`~transplanter.geometry.pitch.arcframe.ArcFrame`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.tolerances import SPIKE_LENGTH

__all__ = ["CAP", "Apart", "apart_spaces", "despike", "lands_between", "space_polygons", "spikes", "tip_lands"]

#: the cap closing a tooth space on the free side, modules beyond its last samples outside the blank
CAP = 0.25


def despike(points: np.ndarray, length: float) -> np.ndarray:
    """Drop vertices where the path turns back (> 90°) on a segment shorter than ``length``.

    Where two pieces of the envelope meet (flank and fillet) the sampled path can overshoot by
    a micrometre and come back: a zero-area spike that is a valid polygon but turns into a
    self-crossing once the DXF fits arcs through it.
    """
    pts = np.asarray(points, dtype=float)
    return pts[despiked_index(pts, length)]


def despiked_index(points: np.ndarray, length: float) -> np.ndarray:
    """Indices of the vertices :func:`despike` keeps."""
    index = np.arange(len(points))
    while len(index) > 3:
        back = np.flatnonzero(spikes(points[index], length)[1:-1]) + 1
        if back.size == 0:
            break
        index = np.delete(index, back[::2])  # every other one, then look again
    return index


def spikes(points: np.ndarray, length: float) -> np.ndarray:
    """Mask of the vertices of paths ``points`` (..., n, 2) where the path turns back (> 90°)
    on a segment shorter than ``length`` (the ends are never spikes)."""
    u = points[..., 1:-1, :] - points[..., :-2, :]
    v = points[..., 2:, :] - points[..., 1:-1, :]
    uu, vv, uv = (np.einsum("...i,...i", a, b) for a, b in ((u, u), (v, v), (u, v)))
    inner = (np.minimum(uu, vv) < length * length) & (uv < 0)
    pad = np.zeros(points.shape[:-2] + (1,), dtype=bool)
    return np.concatenate([pad, inner, pad], axis=-1)


def space_polygons(y, nrm, side, module):
    """Every tooth space as a polygon: its envelope closed 3 m out on the free side (along the
    normals ``nrm`` at the space centres), made valid where the envelope folds (undercut) — they
    overlap outside the blank, so they are unioned."""
    ext = 3.0 * module
    polys = []
    for j in range(y.shape[0]):
        out = side * nrm[j] * ext
        ring = np.concatenate([[y[j, 0] + out], despike(y[j], SPIKE_LENGTH), [y[j, -1] + out]])
        poly = shapely.Polygon(ring)
        if not poly.is_valid:
            poly = shapely.make_valid(poly, method="structure", keep_collapsed=False)
        polys.append(poly)
    return polys


@dataclass(frozen=True)
class Apart:
    """Tooth spaces that neither fold nor touch, as :func:`apart_spaces` found them."""

    #: the spaces, one valid MultiPolygon
    spaces: shapely.MultiPolygon
    #: (spaces, samples) envelope samples that are vertices of the spaces' outlines
    kept: np.ndarray
    #: (spaces, 2) where each envelope enters and leaves the blank: arc length on the pitch curve
    crossings: np.ndarray


def apart_spaces(y, in_blank, s_centres, nrm, frame, side, module, tip, offset, turns=1) -> Apart | None:
    """The tooth spaces as one valid MultiPolygon without a union, or None.

    Each envelope is kept from the last sample before it enters the blank to the first after it
    leaves, and closed by a cap ``CAP`` m out on the free side (along the normals ``nrm`` at the
    space centres ``s_centres``). When every cap stays off the
    blank, no space folds (no undercut loop) and no two touch (a tooth between each pair), the
    spaces are already a valid MultiPolygon — the usual case, and a GEOS union of all spaces
    saved. Otherwise None: :func:`space_polygons` and a union do it, as they always can.
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
    spiky = spikes(y, SPIKE_LENGTH) & kept
    spiky[rows, first] = spiky[rows, last] = False
    for j in np.flatnonzero(spiky.any(axis=1)):  # rare: drop the spikes of these spaces
        index = np.arange(first[j], last[j] + 1)
        kept[j] = False
        kept[j, index[despiked_index(y[j, index], SPIKE_LENGTH)]] = True
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
    return Apart(spaces, kept, (crossings[None] + sectors[:, None, None]).reshape(-1, 2))


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


def lands_between(frame, crossings, offset) -> np.ndarray:
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


def tip_lands(tip, cut, frame, s_centres, side, offset, phase):
    """Length of tip curve left on each tooth, mm (tooth t between spaces t and t+1); ``phase``
    None: a toothed sector, its spaces at ``s_centres`` (increasing arc lengths)."""
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
        if phase is None:
            t = (int(np.searchsorted(s_centres, probe_s[k], side="right")) - 1) % len(s_centres)
        else:
            t = int(math.floor(probe_s[k] / pitch - phase)) % len(s_centres)
        lands[t] += piece.length
    return lands
