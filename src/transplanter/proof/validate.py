"""The made parts judged against their design: do the gears mesh, does the train and the cam move
as designed — one module per proof, gathered here — and was a file turned after the build?

- **Gear pairs**: :func:`transplanter.proof.meshing.mesh_check` meshes the made outlines over the
  cycle — overlap, transmission error, free play, clearance, contacts.
- **Trains**: :func:`transplanter.proof.train_rebuild.train_check` rebuilds the seed-004 train with the
  planet attitude taken from the geometric meshing of the parts.
- **Cams**: :func:`transplanter.proof.follower.follower_check` presses the follower onto the made cam
  contour at each cam angle and compares its motion with the prescribed law.
- **Forensics**: :func:`turned_by` says by how much a made contour is turned from its design.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy import optimize

from transplanter.proof.follower import FollowerReport, follower_check
from transplanter.proof.meshing import MeshReport, mesh_check
from transplanter.proof.train_rebuild import TrainReport, train_check

__all__ = [
    "MeshReport",
    "mesh_check",
    "TrainReport",
    "train_check",
    "FollowerReport",
    "follower_check",
    "turned_by",
]


def turned_by(made, design, max_deg: float = 10.0, band: float = 2e-3) -> float | None:
    """The angle (deg, counter-clockwise about the origin) by which the ``made`` contour
    (shapely polygon) is turned from the ``design``, or None when they already agree (on average
    within ``band`` mm along the contour) or no turn within ``max_deg`` makes them agree.

    ``check`` uses it to say "this file was rotated" instead of letting the meshing figures blame
    the centre distance or the tooth counts."""
    limit = band * design.exterior.length

    def mismatch(deg: float) -> float:
        turned = shapely.affinity.rotate(made, -deg, origin=(0.0, 0.0))
        return float(shapely.symmetric_difference(turned, design).area)

    if mismatch(0.0) <= limit:
        return None
    scan = np.arange(-max_deg, max_deg + 1e-9, 0.25)
    k = int(np.argmin([mismatch(a) for a in scan]))
    best = optimize.minimize_scalar(mismatch, bounds=(scan[k] - 0.25, scan[k] + 0.25), method="bounded")
    return float(best.x) if best.fun <= limit else None
