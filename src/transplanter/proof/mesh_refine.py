"""Between the samples: the extremes of a meshing sweep refined where a grid would step over them.

Free play and clearance are piecewise smooth in the driver angle: smooth while the same
vertex–edge pairs bound them, with kinks and jumps where the bounding pair changes — the free
play of the seed-004 pair falls linearly by 85 µm over 1° while a planet tip slides down a ring
flank, then jumps back when the tip leaves the ring's tip corner. A sample grid steps over such a
dip's floor — and, dips being 0.6–1° wide, over whole dips (the default 2° grid saw two of the
eight on that pair). So first every close pass of a tooth tip is found on a 0.1° scan of the tips
alone (:func:`approaches`) and measured exactly; then every local extreme of the samples is
refined by bisection of the intervals beside it (:func:`refine`), until each such interval is
narrower than ``REFINE_RAD`` or the values at its ends differ by less than ``REFINE_MM``: a jump
is located to 1e-5 rad of driver turn and its floor taken from the side where the function is
continuous, a smooth extreme to 0.5 µm. An extreme's figure is the extreme over the uniform and
the refined samples, with the angle where it lies. What this still assumes (it is not a certified
bound): a dip is made by a tip passing the other gear and lasts longer than the scan step, or
shows in a uniform sample; ``tests/test_meshing.py`` holds the refined extremes to a 200× denser
judge.
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.extrema import prominent_peaks
from transplanter.core.tolerances import REFINE_MM, REFINE_RAD
from transplanter.geometry import contact
from transplanter.proof.mesh_engine import CLEARANCE_CAP_MM, MESH_CHUNK, MeshSweep

__all__ = ["APPROACH_STEPS", "DIP_PROMINENCE_MM", "REFINE_ROUNDS", "TIP_BAND_MODULES", "approaches", "refine"]

#: refinement rounds at most (each halves the intervals beside every extreme; 0.05 rad -> 1e-5 in 13)
REFINE_ROUNDS = 20


def _extremes(f: np.ndarray) -> np.ndarray:
    """Indices (into the sorted cyclic samples ``f``) of the local minima of ``f`` that the samples
    around them could hide a lower value beside: every local minimum whose drop to a
    neighbour reaches below the lowest sample (a jump, or the global minimum itself)."""
    left, right = np.roll(f, 1), np.roll(f, -1)
    local = (f <= left) & (f <= right)
    reach = f - np.maximum(left - f, right - f)
    return np.flatnonzero(local & (reach <= f.min() + REFINE_MM))


#: tip passes are scanned on a grid of this many driver positions per turn (module docstring)
APPROACH_STEPS = 3600
#: the vertices within this many modules of a gear's tip radius are its tips for that scan
TIP_BAND_MODULES = 0.35
#: a tip pass counts as a dip when it stands out of its surroundings by this much, mm
DIP_PROMINENCE_MM = 2e-3


def approaches(mesh: MeshSweep) -> np.ndarray:
    """Driver angles (rad) where a tooth tip of either gear passes closest to the other gear's
    outline — the places where the free play and the clearance dip — found on a grid of
    ``APPROACH_STEPS`` positions from the tips alone (the few vertices near each tip radius,
    with the driven gear at its design angle plus the mean play centre): each minimum of that
    distance that stands out of its surroundings by ``DIP_PROMINENCE_MM`` (within
    ``CLEARANCE_CAP_MM``), where no uniform sample lies within a grid step. A heuristic that finds
    candidates, not a bound: what it finds is then measured exactly and refined.

    A tip passing a flank makes a dip 0.6–1° wide on the seed-004 pair (free play falling by
    85 µm); the uniform meshing grid (2°) saw two of its eight copies, this scan (0.1°) all."""
    drv, drn, c = mesh.drv, mesh.drn, mesh.centre
    band = TIP_BAND_MODULES * mesh.module
    tips = []
    for outline, ring in ((drv, mesh.pair.ring == "driver"), (drn, mesh.pair.ring == "driven")):
        r = np.hypot(outline.xy[:, 0], outline.xy[:, 1])
        tips.append(np.flatnonzero(r <= outline.r_min + band) if ring else np.flatnonzero(r >= outline.r_max - band))
    phi = 2 * math.pi * np.arange(APPROACH_STEPS) / APPROACH_STEPS
    grid = MeshSweep.like(mesh, phi)
    centre = float(np.mean(mesh.te + 0.5 * mesh.bl / mesh.r2))  # the mean play centre, rad
    psi1, psi2 = grid.psi1, grid.psi2 + mesh.turn * centre
    edges1, edges2 = mesh.index[:2]
    near = np.full(APPROACH_STEPS, np.inf)
    for start in range(0, APPROACH_STEPS, 4 * MESH_CHUNK):
        k = np.arange(start, min(APPROACH_STEPS, start + 4 * MESH_CHUNK))
        # driver tips in the driven frame, driven tips in the driver frame
        s1 = np.repeat(np.arange(len(k)), len(tips[0]))
        b1 = contact.rotate(drv.placed(np.tile(tips[0], len(k)), psi1[k], -c, s1), -psi2[k], s1)
        keep = drn.near(b1, mesh.pair.ring == "driven", CLEARANCE_CAP_MM)
        d1, _ = edges2.nearest(b1[keep], s1[keep], len(k))
        s2 = np.repeat(np.arange(len(k)), len(tips[1]))
        b2 = contact.rotate(drn.placed(np.tile(tips[1], len(k)), psi2[k], c, s2), -psi1[k], s2)
        keep = drv.near(b2, mesh.pair.ring == "driver", CLEARANCE_CAP_MM)
        d2, _ = edges1.nearest(b2[keep], s2[keep], len(k))
        near[k] = np.minimum(d1, d2)
    # a pass is a dip where the tips come closer than around it: a minimum standing out of its
    # surroundings by more than DIP_PROMINENCE_MM (the flank-gap plateau between passes has
    # minima of round-off depth); the grid is extended by a turn each way, so none wraps
    n = APPROACH_STEPS
    peaks = prominent_peaks(-np.tile(np.minimum(near, CLEARANCE_CAP_MM), 3), DIP_PROMINENCE_MM)
    mine = (peaks >= n) & (peaks < 2 * n)
    peaks = peaks[mine] - n
    dips = np.unique(peaks)
    found = phi[dips]
    step = 2 * math.pi / APPROACH_STEPS
    gap = np.abs(contact.wrap(found[:, None] - mesh.phi1[None, :])).min(axis=1) if len(found) else found
    return found[gap > step]


def refine(mesh: MeshSweep):
    """Sample every close tip pass (:func:`approaches`), then bisect the intervals beside every
    extreme of the free play (both ways) and the clearance (its minimum) until narrower than
    REFINE_RAD or resolved to REFINE_MM; returns the added samples (angle, backlash, clearance)
    and the nearest points at the smallest clearance."""
    columns = [(mesh.phi1, mesh.bl, mesh.clear, mesh.clear_points)]  # uniform, then each batch added

    def sample(phi):
        more = MeshSweep.like(mesh, phi)
        more.all()
        columns.append((more.phi1, more.bl, more.clear, more.clear_points))

    seen = approaches(mesh)
    if len(seen):
        sample(seen)
    for _ in range(REFINE_ROUNDS):
        phi, bl, cl = (np.concatenate([c[k] for c in columns]) for k in range(3))
        order = np.argsort(phi)
        p, b, c = phi[order], bl[order], cl[order]
        gap = np.diff(p, append=p[0] + 2 * math.pi)  # interval after each sample
        new = []
        for f in (b, -b, c):
            for i in _extremes(f):
                for j in ((i - 1) % len(p), i):  # the intervals before and after sample i
                    if gap[j] > REFINE_RAD and abs(f[(j + 1) % len(p)] - f[j]) > REFINE_MM:
                        new.append(p[j] + 0.5 * gap[j])
        if not new:
            break
        sample(np.unique(np.mod(new, 2 * math.pi)))
    phi, bl, cl, pts = (np.concatenate([c[k] for c in columns]) for k in range(4))
    n0 = len(mesh.phi1)
    return phi[n0:], bl[n0:], cl[n0:], pts[int(np.argmin(cl))]
