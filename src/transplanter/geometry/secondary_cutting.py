"""Secondary cutting: whether a shaper's other teeth reach into the gear it has finished.

The finished gear must not overlap the cutter at any roll position; where it does, the cutter's
other teeth would have cut it (secondary cutting on ring gears, or interference).
:func:`transplanter.geometry.teeth.generate` runs :func:`secondary_cut` on every ring it cuts and
refuses a reach deeper than four chord tolerances; a toothed sector is checked only
``SECTOR_RUN_OUT`` pitches clear of its ends.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from transplanter.core.tolerances import CHORD_TOLERANCE
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.envelope import _on_gear
from transplanter.geometry.pitch.arcframe import ArcFrame

__all__ = ["SECTOR_RUN_OUT", "secondary_cut"]


#: a toothed sector's spaces this many pitches from its ends are left out of the secondary-cut
#: check: there a shaper's other teeth reach the uncut rest of the blank (run-out, not a defect of
#: the envelope the wire follows)
SECTOR_RUN_OUT = 3


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
    centres=None,
):
    """Deepest reach (mm) of any cutter position into the finished ``body``, and its roll (mm).

    Reaches below CHORD_TOLERANCE count as contact and give 0.

    The finished gear must not overlap the cutter at any roll position; where it does, the
    cutter's other teeth would have cut it (secondary cutting on ring gears, or interference).
    A gear that turns onto itself ``turns`` times a revolution (``teeth._symmetry``) is checked
    over one such sector: the others repeat it. ``centres`` (a toothed sector's space centres,
    arc lengths) limits the rolls to the sector, ``SECTOR_RUN_OUT`` pitches clear of its ends.
    """
    if centres is not None:
        pitch = cutter.pitch
        # within the sector only: at its ends a shaper's other teeth would cut the uncut rest of the
        # blank (a shaped sector needs run-out there; the outline is the envelope, made by the wire)
        inner = np.diff(centres) < 1.01 * pitch  # a pitch apart: within a sector
        runs = np.split(np.arange(len(centres)), np.flatnonzero(~inner) + 1)
        ends = SECTOR_RUN_OUT
        gaps = np.concatenate(
            [r[ends : len(r) - 1 - ends] for r in runs if len(r) > 2 * ends + 1] or [np.zeros(0, int)]
        )
        s = (centres[gaps, None] + pitch * np.arange(per_pitch) / per_pitch).ravel()
        j = centres[np.argmin(np.abs(s[:, None] - centres[None, :]), axis=1)]
    else:
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
        margin = cutter.m
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
