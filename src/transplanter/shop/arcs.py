"""Arc fitting and bulge arithmetic: closed contours as tangent-continuous circular arcs (numpy
only; the DXF writer and reader, :mod:`transplanter.shop.dxf`, sit above it, as ezdxf keeps its
``math/`` free of entities).

**Arc fitting.** A closed contour (polyline whose vertices lie on the exact curve) is split at
corners (turning angle > ``corner_deg``) and each smooth stretch is covered greedily by
circular arcs that are *tangent-continuous*: every arc starts with the end tangent of the one
before, and reaches as far as it can while every vertex and every chord midpoint of the
source stays within ``tolerance`` of it (exponential then binary search). Where no tangent
arc fits even one step, the chain breaks there and a free three-point arc starts. The result
is a list of *bulge vertices* ``(n, 3)``: x, y and the bulge ``tan(θ/4)`` of the arc to the
next vertex (0 for a line), with no gaps and no segment shorter than ``min_segment``.
:func:`section_arcs` fits a part section one-sided: every ring first moved into the material
(:func:`machining.inset_ring`), so the arcs never add material.

Examples
--------
>>> import numpy as np
>>> from transplanter.shop.arcs import fit_arcs
>>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
>>> ellipse = np.stack([40 * np.cos(t), 25 * np.sin(t)], axis=1)
>>> verts = fit_arcs(ellipse, tolerance=1e-3)
>>> len(verts) < 2000 // 10  # G1 arcs within 1 µm: 107 here against 2000 points
True
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from transplanter.core.errors import SpecError
from transplanter.core.tolerances import DXF_ARC_TOLERANCE_MM, DXF_INSET_MM
from transplanter.shop.machining import inset_ring

__all__ = ["bulge_area", "bulge_points", "fit_arcs", "section_arcs", "with_arcs"]


def _arc_dev(p0, t0, p1, pts):
    """Tangent arc from p0 (unit tangent t0) to p1: bulge and max |distance| of pts from it."""
    d = p1 - p0
    cross = t0[0] * d[1] - t0[1] * d[0]
    dot = t0[0] * d[0] + t0[1] * d[1]
    theta = 2 * math.atan2(cross, dot)  # included angle, signed (CCW positive)
    if abs(theta) < 1e-12:  # straight
        n = np.array([-d[1], d[0]]) / max(np.hypot(*d), 1e-300)
        return 0.0, float(np.max(np.abs((pts - p0) @ n))) if len(pts) else 0.0, theta
    chord = math.hypot(*d)
    radius = chord / (2 * math.sin(theta / 2))  # signed
    normal = np.array([-t0[1], t0[0]])
    centre = p0 + radius * normal
    dev = np.abs(np.hypot(pts[:, 0] - centre[0], pts[:, 1] - centre[1]) - abs(radius)) if len(pts) else np.zeros(1)
    return math.tan(theta / 4), float(np.max(dev)), theta


def _three_point_tangent(p0, pm, p1):
    """Start tangent of the circle through p0, pm, p1 (unit), or the chord direction if collinear."""
    a, b = pm - p0, p1 - p0
    cross = a[0] * b[1] - a[1] * b[0]
    if abs(cross) < 1e-15 * max(1.0, np.dot(b, b)):
        return b / np.hypot(*b)
    # circle centre
    d = 2 * cross
    ux = (b[1] * np.dot(a, a) - a[1] * np.dot(b, b)) / d
    uy = (a[0] * np.dot(b, b) - b[0] * np.dot(a, a)) / d
    r = np.array([ux, uy])  # centre relative to p0; the tangent is r turned by -90° (CCW) or +90° (CW)
    t = np.array([r[1], -r[0]]) if cross > 0 else np.array([-r[1], r[0]])
    return t / np.hypot(*t)


def _rotate(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _fit_chain(pts: np.ndarray, tol: float, t_start=None):
    """Tangent-continuous arcs over the open chain ``pts``; returns [(point, bulge), ...] without the end."""
    out = []
    n = len(pts)
    i = 0
    t = t_start
    mids = 0.5 * (pts[1:] + pts[:-1])

    def check(i, j, tangent):
        inner = np.concatenate([pts[i + 1 : j], mids[i:j]])
        return _arc_dev(pts[i], tangent, pts[j], inner)

    while i < n - 1:
        tangent = t if t is not None else _three_point_tangent(pts[i], pts[min(i + 1, n - 1)], pts[min(i + 2, n - 1)])
        bulge, dev, theta = check(i, i + 1, tangent)
        if dev > tol and t is not None:  # the inherited tangent does not fit: break G1 here
            tangent = _three_point_tangent(pts[i], pts[min(i + 1, n - 1)], pts[min(i + 2, n - 1)])
            bulge, dev, theta = check(i, i + 1, tangent)
        if dev > tol:  # even the free tangent fails over one step: a straight segment is exact
            tangent = (pts[i + 1] - pts[i]) / np.hypot(*(pts[i + 1] - pts[i]))
            bulge, dev, theta = check(i, i + 1, tangent)
        good, good_fit = i + 1, (bulge, theta)
        step = 1
        while good + step < n:
            b2, dev2, th2 = check(i, good + step, tangent)
            if dev2 > tol or abs(th2) > math.pi:
                break
            good, good_fit = good + step, (b2, th2)
            step *= 2
        lo, hi = good, min(good + step, n - 1)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            b2, dev2, th2 = check(i, mid, tangent)
            if dev2 <= tol and abs(th2) <= math.pi:
                lo, good_fit = mid, (b2, th2)
            else:
                hi = mid
        good = lo
        out.append((pts[i], good_fit[0]))
        t = _rotate(tangent, good_fit[1])
        i = good
    return out


def fit_arcs(points, tolerance: float = 0.5e-3, corner_deg: float = 20.0, min_segment: float = 1e-3):
    """Bulge vertices ``(n, 3)`` [x, y, bulge] of arcs within ``tolerance`` of the closed ``points``.

    Consecutive points closer than ``min_segment`` (mm) are merged first.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3 or not np.all(np.isfinite(pts)):
        raise SpecError("fit_arcs needs a closed contour of at least 3 finite (x, y) points")
    if np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    # merge points closer than min_segment, keeping the one where the contour turns more (a
    # corner dropped in favour of its neighbour would be cut off by up to min_segment)
    d_in = pts - np.roll(pts, 1, axis=0)
    d_out = np.roll(pts, -1, axis=0) - pts
    bend = np.abs(np.angle(np.exp(1j * (np.arctan2(d_out[:, 1], d_out[:, 0]) - np.arctan2(d_in[:, 1], d_in[:, 0])))))
    keep = [0]
    for k in range(1, len(pts)):
        if np.hypot(*(pts[k] - pts[keep[-1]])) >= min_segment:
            keep.append(k)
        elif keep[-1] != 0 and bend[k] > bend[keep[-1]] and np.hypot(*(pts[k] - pts[keep[-2]])) >= min_segment:
            keep[-1] = k
    pts = pts[keep]
    if np.hypot(*(pts[-1] - pts[0])) < min_segment:
        pts = pts[:-1]
    seg = np.roll(pts, -1, axis=0) - pts
    ang_in = np.arctan2(np.roll(seg, 1, axis=0)[:, 1], np.roll(seg, 1, axis=0)[:, 0])
    ang_out = np.arctan2(seg[:, 1], seg[:, 0])
    turn = np.abs(np.angle(np.exp(1j * (ang_out - ang_in))))
    corners = np.flatnonzero(turn > math.radians(corner_deg))
    start = int(corners[0]) if corners.size else 0
    pts = np.roll(pts, -start, axis=0)
    corners = np.sort((corners - start) % len(pts)) if corners.size else np.array([0])
    bounds = list(corners) + [len(pts)]
    loop = np.vstack([pts, pts[:1]])
    verts = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        if b <= a:
            continue
        verts.extend(_fit_chain(loop[a : b + 1], tolerance))
    return np.array([[p[0], p[1], bulge] for p, bulge in verts])


def bulge_area(verts: np.ndarray) -> float:
    """Signed area (mm², counter-clockwise positive) enclosed by closed bulge vertices ``(n, 3)``:
    the polygon of the vertices plus each arc's circular segment ``R²/2 (θ - sin θ)``, signed
    with its bulge (``θ = 4 atan(bulge)``) — exact for lines and arcs."""
    v = np.asarray(verts, dtype=float)
    x, y, b = v[:, 0], v[:, 1], v[:, 2]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    area = 0.5 * float(np.sum(x * yn - xn * y))
    theta = 4.0 * np.arctan(b[b != 0])
    chord = np.hypot(xn - x, yn - y)[b != 0]
    r = chord / (2.0 * np.abs(np.sin(theta / 2)))
    return area + float(np.sum(np.sign(theta) * r**2 / 2 * (np.abs(theta) - np.sin(np.abs(theta)))))


def bulge_points(verts: np.ndarray, sagitta: float = 1e-3) -> np.ndarray:
    """Closed bulge vertices ``(n, 3)`` flattened to points ``(m, 2)`` (the first not repeated),
    each arc sampled so that no chord leaves it by more than ``sagitta`` mm. An arc's centre and
    start are found in Python floats (the same operations numpy did on each vertex, in the same
    order: the same bits, without numpy's cost per vertex), its points by :func:`with_arcs`."""
    v = np.asarray(verts, dtype=float)
    rows = v.tolist()
    arcs = []
    for k, (x0, y0, b) in enumerate(rows):
        if b == 0.0:
            continue
        x1, y1 = rows[(k + 1) % len(rows)][:2]
        theta = 4.0 * math.atan(b)
        dx, dy = x1 - x0, y1 - y0
        c = math.hypot(dx, dy)
        r = c / (2.0 * math.sin(theta / 2))  # signed: the centre lies left of the chord for b > 0
        h = math.cos(theta / 2)
        cx, cy = (x0 + x1) / 2 + -dy / c * r * h, (y0 + y1) / 2 + dx / c * r * h
        steps = max(1, math.ceil(abs(theta) / (2 * math.acos(max(-1.0, 1 - sagitta / abs(r))))))
        arcs.append((k, cx, cy, abs(r), math.atan2(y0 - cy, x0 - cx), theta, steps, False))
    return with_arcs(v[:, :2], arcs)


def with_arcs(xy: np.ndarray, arcs: list[tuple]) -> np.ndarray:
    """The points ``xy`` (n, 2) of a closed polyline, each vertex followed by the inner points of
    the arc that starts there: ``arcs`` rows ``(vertex, cx, cy, r, a0, sweep, steps, reversed)``, the
    arc's points at ``a0 + sweep × i / steps`` for i = 1 … steps − 1 about the centre (cx, cy) at
    radius r (in the reverse order where ``reversed``) — every arc at once, each point computed
    with the operations a loop over the arcs would do, in the same order (the same bits)."""
    if not arcs:
        return np.array(xy, dtype=float)
    k, cx, cy, r, a0, sweep, steps, rev = (np.array(column) for column in zip(*arcs, strict=True))
    inner = steps - 1
    count = np.ones(len(xy), dtype=np.intp)
    count[k] += inner
    first = np.cumsum(count) - count
    out = np.empty((int(count.sum()), 2))
    out[first] = xy
    arc = np.repeat(np.arange(len(arcs)), inner)
    j = np.arange(int(inner.sum())) - np.repeat(np.cumsum(inner) - inner, inner)  # 0 … inner - 1
    ang = a0[arc] + sweep[arc] * (j + 1) / steps[arc]
    at = first[k][arc] + 1 + np.where(rev[arc], inner[arc] - 1 - j, j)
    out[at, 0] = cx[arc] + r[arc] * np.cos(ang)
    out[at, 1] = cy[arc] + r[arc] * np.sin(ang)
    return out


def _rings(section: shapely.Polygon):
    yield np.asarray(section.exterior.coords), False
    for r in section.interiors:
        yield np.asarray(r.coords), True


def section_arcs(section: shapely.Polygon, tolerance: float = DXF_ARC_TOLERANCE_MM, inset: float = DXF_INSET_MM):
    """The contours of ``section`` as one-sided arc fits: ``[(verts (n, 3), is_hole), ...]``.

    Every ring is first moved ``inset`` into the material (:func:`inset_ring`), then fitted
    within ``tolerance``; with ``inset > tolerance`` the arcs never add material to the part.
    """
    oriented = shapely.geometry.polygon.orient(section, 1.0)
    return [(fit_arcs(inset_ring(ring, inset), tolerance), inner) for ring, inner in _rings(oriented)]
