"""What a moving body sweeps through another's frame: the relief of incomplete gears.

:func:`swept` poses the driver of an :class:`~transplanter.geometry.pitch.intermittent.IncompletePair` in
its driven gear's body frame over a span of driver angles — the driven at its law's angle, so
standing still over a dwell and rolling over a motion — and unites, between every two poses,
the convex hull of each edge's two positions (:func:`edge_hulls`: exact for the straight motion
of an edge; the arc each point really follows strays from its chord by at most ``d δ² / 8``, ``d``
its distance from the instantaneous centre, ``δ`` the relative turn — twice that bound is added
to the growth), and the two end poses whole. Clipper2 (manifold3d ``CrossSection``) unites them a
few pose steps at a time (``SWEEP_CHUNK``: a hundred thousand overlapping triangles at once cost
it ten times more than the same in chunks), the chunks in one batch, and grows the result by the
clearance.
"""

from __future__ import annotations

import math

import manifold3d
import numpy as np
import shapely

from transplanter.geometry.pitch import driven_axis, driven_turn
from transplanter.geometry.pitch.intermittent import IncompletePair

__all__ = ["swept", "edge_hulls", "posed_in", "turned", "SWEEP_STEP_DEG", "SWEEP_SIMPLIFY_MM", "SWEEP_CHUNK"]

#: pose step of the sweep, driver degrees (its chord error is added to the growth)
SWEEP_STEP_DEG = 1.0
#: the driver's outline is simplified by this for the sweep (added to the growth), mm
SWEEP_SIMPLIFY_MM = 0.5e-3
#: pose steps whose edge hulls are united at once (module docstring)
SWEEP_CHUNK = 4
#: circle segments of the growth's round joins (chord error c (1 - cos π/n) < 0.1 µm)
ROUND_SEGMENTS = 128


def turned(points: np.ndarray, angle) -> np.ndarray:
    """Points (..., 2) turned about the origin by ``angle`` (rad; broadcast against the points)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * points[..., 0] - s * points[..., 1], s * points[..., 0] + c * points[..., 1]], axis=-1)


def posed_in(points: np.ndarray, pair: IncompletePair, phi: np.ndarray, each: bool = False) -> np.ndarray:
    """Driver body points (n, 2) in the driven's body frame at driver angles ``phi`` (rad):
    (poses, n, 2); with ``each``, one point per angle: (n, 2). The meshing conventions: driver
    clockwise about the origin, the driven's axis at (a, 0) (a ring's at (-a, 0))."""
    centre, psi2 = driven_axis(pair), driven_turn(pair, phi)
    if each:
        return turned(turned(points, -phi) - (centre, 0.0), -psi2)
    return turned(turned(points[None], -phi[:, None]) - (centre, 0.0), -psi2[:, None])


def swept(driver: shapely.Polygon, pair: IncompletePair, window: tuple[float, float], grow: float, reach):
    """The region ``driver`` (its body frame), grown by ``grow`` (mm), sweeps through the driven's
    body frame while the driver turns over ``window`` (rad) and the driven follows its law;
    ``reach(q)`` admits the driven-frame points that can meet driven material (module docstring)."""
    body = driver.simplify(SWEEP_SIMPLIFY_MM)
    rings = [np.asarray(body.exterior.coords)[:-1], *(np.asarray(i.coords)[:-1] for i in body.interiors)]
    step = math.radians(SWEEP_STEP_DEG)
    phi = np.linspace(window[0], window[1], max(2, int(math.ceil((window[1] - window[0]) / step))) + 1)
    # the end poses whole, then the edge hulls a few steps at a time: Clipper2 unites a few thousand
    # overlapping triangles at once far faster than a hundred thousand (each chunk's union is
    # small), and the chunks' unions are then united in one batch
    ends = posed_in(rings[0], pair, phi[[0, -1]])
    near = reach(ends).any(axis=1)
    sections = (
        [manifold3d.CrossSection(_oriented([p for p, n in zip(ends, near, strict=True) if n]))] if near.any() else []
    )
    chord = 0.0
    for k in range(0, len(phi) - 1, SWEEP_CHUNK):
        contours: list[np.ndarray] = []
        for ring in rings:
            found, err = edge_hulls(ring, pair, phi[k : k + SWEEP_CHUNK + 1], reach)
            contours.extend(found)
            chord = max(chord, err)
        if contours:
            sections.append(manifold3d.CrossSection(contours, manifold3d.FillRule.NonZero))
    if not sections:
        return shapely.Polygon()
    section = (
        manifold3d.CrossSection.batch_boolean(sections, manifold3d.OpType.Add) if len(sections) > 1 else sections[0]
    )
    section = section.offset(grow + chord + SWEEP_SIMPLIFY_MM, manifold3d.JoinType.Round, 2.0, ROUND_SEGMENTS)
    return _shapely(section)


def _oriented(contours: list[np.ndarray]) -> list[np.ndarray]:
    """Closed contours turned counter-clockwise (for the non-zero fill)."""
    out = []
    for c in contours:
        x, y = c[:, 0], c[:, 1]
        signed = float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
        out.append(c if signed > 0 else c[::-1])
    return out


def edge_hulls(ring: np.ndarray, pair: IncompletePair, phi: np.ndarray, reach):
    """Contours of the region a closed ``ring`` of driver points sweeps through the driven's frame
    over the driver angles ``phi``: between every two poses the convex hull of each edge's two
    positions that ``reach`` admits (two triangles where the four points make a convex quad, else
    the four of the hull), counter-clockwise; and the chord error of the poses (mm)."""
    posed = posed_in(ring, pair, phi)  # (poses, n, 2)
    near = reach(posed)
    out: list[np.ndarray] = []
    a0, a1 = posed[:-1], np.roll(posed[:-1], -1, axis=1)
    b0, b1 = posed[1:], np.roll(posed[1:], -1, axis=1)
    use = near[:-1] | np.roll(near[:-1], -1, axis=1) | near[1:] | np.roll(near[1:], -1, axis=1)
    if not use.any():
        return out, 0.0
    q = np.stack([a0[use], a1[use], b1[use], b0[use]], axis=1)  # (m, 4, 2)
    e = np.roll(q, -1, axis=1) - q
    turns = e[:, :, 0] * np.roll(e, -1, axis=1)[:, :, 1] - e[:, :, 1] * np.roll(e, -1, axis=1)[:, :, 0]
    convex = np.all(turns > 0, axis=1) | np.all(turns < 0, axis=1)
    pick = [(0, 1, 2), (0, 2, 3)]
    tri = [q[convex][:, list(t)] for t in pick]
    tri += [q[~convex][:, list(t)] for t in ((0, 1, 2), (0, 2, 3), (0, 1, 3), (1, 2, 3))]
    tri = np.concatenate(tri)
    area = (tri[:, 1, 0] - tri[:, 0, 0]) * (tri[:, 2, 1] - tri[:, 0, 1]) - (tri[:, 2, 0] - tri[:, 0, 0]) * (
        tri[:, 1, 1] - tri[:, 0, 1]
    )
    keep = np.abs(area) > 1e-16
    tri, area = tri[keep], area[keep]
    tri[area < 0] = tri[area < 0][:, ::-1]
    out.extend(tri)
    # each point follows a roulette about the pitch point (the driver's axis in a dwell): between
    # two poses it strays from its chord by at most d δ² / 8 (d its distance from that centre,
    # δ the relative turn); twice that bound is taken
    psi = pair.law.psi(phi)
    rel = np.abs(np.diff(phi + (psi if pair.mesh == "external" else -psi)))
    r1 = pair.driver.r(phi)
    pitch_pt = posed_in(np.column_stack([r1 * np.cos(phi), r1 * np.sin(phi)]), pair, phi, each=True)
    d = np.linalg.norm(posed[:-1] - pitch_pt[:-1, None, :], axis=2)
    d = np.where(use, d, 0.0).max(axis=1)
    return out, float(np.max(d * rel**2 / 4))


def _shapely(section) -> shapely.Geometry:
    """A manifold3d CrossSection as one shapely geometry (its contours by even-odd)."""
    polys = [shapely.Polygon(c) for c in section.to_polygons() if len(c) >= 3]
    out = shapely.Polygon()
    for p in polys:
        out = shapely.symmetric_difference(out, p)
    return shapely.make_valid(out) if not out.is_valid else out
