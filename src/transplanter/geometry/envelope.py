"""The envelope of a gear cutter rolling on a pitch curve, sampled to a chord tolerance.

A cutter profile point touches the envelope at the roll its :class:`~transplanter.geometry.cutter_tooth.Cutter`
gives in closed form (``contact_rolls``), where the cutter is then placed (``placement``): the
point turned and moved into the gear frame (``_on_gear``) is an exact envelope point (``_contact``;
the meshing condition is :mod:`transplanter.geometry.teeth`'s module docstring). The profile
parameter τ is refined until every chord of every space lies within the tolerance of the
envelope (``_profile_grid``). A gear that turns onto itself is sampled on one sector and turned
onto the others (``_turned``), its tip curve — the pitch curve moved along its normal — too
(``_offset``, ``_tip_region``).

These are the working of :func:`transplanter.geometry.teeth.generate` and of the
secondary-cutting check (:mod:`~transplanter.geometry.secondary_cutting`): no public name.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from transplanter.geometry.cutter_tooth import Cutter
from transplanter.geometry.pitch.arcframe import ArcFrame

__all__: list[str] = []


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
