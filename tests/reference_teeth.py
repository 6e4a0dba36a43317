"""The brute-force reference for the envelope teeth: the gear blank minus the union of the cutter
placed at many roll positions (shapely), and the distance of exact flank points from it.

What a user with shapely would do (ANCHORS.md's Boolean envelope); ``tests/test_teeth.py``
holds :func:`transplanter.geometry.teeth.generate` to it within 1 µm and ``benchmarks/teeth.py`` times
both. Not part of the library: it only checks it.
"""

import numpy as np
import shapely

from transplanter.core.tolerances import CHORD_TOLERANCE
from transplanter.geometry.cutter import Cutter, RackCutter, ShaperCutter
from transplanter.geometry.envelope import _offset, _on_gear, _tip_region
from transplanter.geometry.pitch import PitchCurve
from transplanter.geometry.teeth import ArcFrame, ToothedGear


def boolean_reference(
    curve: PitchCurve,
    cutter: Cutter,
    teeth: int,
    positions: int,
    *,
    internal: bool = False,
    shift: float = 0.0,
    addendum: float = 1.0,
    spaces: list[int] | None = None,
    window: float = 1.5,
    cutter_teeth: int | None = 5,
    per_piece: int = 48,
) -> shapely.Geometry:
    """Brute force: blank minus the union of the cutter outline at ``positions`` rolls per pitch.

    Only ``spaces`` (default all) are cut, each over ``± window`` pitches around its centre,
    by the ``cutter_teeth`` teeth nearest the contact (a sector of the cutter; None = the whole
    cutter), each cutter tooth outline sampled with ``per_piece`` points per profile piece.
    Kept as the reference for tests and benchmarks; the result is the gear body near those
    spaces (cusps between positions leave material, never overcut).
    """
    m = cutter.module
    side = -1.0 if internal else 1.0
    frame = ArcFrame.from_curve(curve)
    pitch = frame.length / teeth
    idx = range(teeth) if spaces is None else spaces
    if isinstance(cutter, RackCutter):
        outline = cutter.outline(per_piece=per_piece, teeth=cutter_teeth or 9)
    else:
        outline = cutter.outline(per_piece=per_piece)
    if isinstance(cutter, ShaperCutter) and cutter_teeth is not None and cutter_teeth < cutter.teeth:
        per_tooth = len(outline) // cutter.teeth
        half = cutter_teeth // 2
        teeth_pts = np.roll(outline, half * per_tooth, axis=0)[: cutter_teeth * per_tooth]
        outline = np.concatenate([teeth_pts, [[0.0, 0.0]]])
    polys = []
    for j in idx:
        sc = j * pitch
        s = sc + pitch * np.linspace(-window, window, int(2 * window * positions) + 1)
        c, psi = cutter.placement(frame, s, sc, side, shift)
        polys.extend(shapely.polygons(_on_gear(c[:, None, :], psi[:, None], outline)))
    cut = shapely.union_all(polys)
    tip = _tip_region(frame, side * (addendum + shift) * m, CHORD_TOLERANCE)
    if internal:
        r = 2 * float(np.max(np.linalg.norm(_offset(frame, 3 * m, CHORD_TOLERANCE), axis=1)))
        disc = shapely.Point(0, 0).buffer(r, 256)
        return shapely.difference(disc, shapely.union(tip, cut))
    return shapely.difference(tip, cut)


def flank_deviation(gear: ToothedGear, reference: shapely.Geometry, spaces: list[int] | None = None) -> float:
    """Largest distance (mm) from the exact flank points of ``spaces`` to the reference boundary.

    Only flank points inside the gear's tip region and on the gear's boundary count (trimmed or
    undercut parts are excluded).
    """
    idx = range(gear.teeth) if spaces is None else spaces
    body_boundary = gear.polygon.boundary
    ref_boundary = reference.boundary
    worst = 0.0
    for j in idx:
        sp = gear.spaces[j]
        pts = shapely.points(np.concatenate([sp.lower, sp.upper]))
        on = shapely.distance(body_boundary, pts) < 1e-6
        if on.any():
            worst = max(worst, float(shapely.distance(ref_boundary, pts[on]).max()))
    return worst
