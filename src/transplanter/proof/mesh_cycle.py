"""Tooth load and stress along one mesh of two made gears over the machine's cycle.

At each position the poses of the two gears (from the machine's posed chain) and the torque the
mesh puts on gear 1 (the *loaded* gear, a planet) are given. The loaded flanks are closed as the
meshing proof closes them (:mod:`~transplanter.proof.meshing`): gear 1 is turned about its centre
from its designed angle, the way its load pushes it (against the mesh torque), by the smallest angle
at which a vertex of one outline meets an edge of the other — in closed form, every position at
once (:mod:`transplanter.geometry.contact`: radius-matched vertex/edge pairs, circle/segment
crossings). The contact places there are the runs of gear 1's boundary within ``contact_tol`` of
gear 0; each is rated by :func:`~transplanter.proof.mesh_load.mesh_contact_load` at its point and
common normal (the normal of the edge the touching vertex lies on): ``F = |T|/ℓ`` with ℓ the
normal's lever about gear 1's centre, Hertz with both flanks' local radii, and the root stress of
both loaded teeth.

**Load sharing**: where two tooth pairs are within ``contact_tol`` at once, *each* is rated as if it
carried the whole torque (``F_i = |T|/ℓ_i``). Conservative: the split depends on the teeth's
stiffness and on errors of the made teeth larger than the gap (the tolerance budget is ~30 µm,
``contact_tol`` 2 µm), neither of which the outlines give.

**Corners**: where the touching vertex is a corner of its outline (a tip corner, edges turning by
more than 30°), the flank ending there rolls on the other flank when the other's normal is that
flank's within ``TANGENT_DEG`` (the ends of the path of contact): its radius is measured half a
fit window in from the corner. Otherwise, or where that flank's end cannot roll on the other (a
tighter concave fillet), the corner pokes the flank — an *edge contact*: no Hertz stress (None,
``sigma_h`` NaN if it is the position's only place), the root stresses still rated, and the
count and the largest such force reported (``max_corner_force``, ``note``).

**Teeth and flanks** are named in each gear's own (DXF) frame: a tooth by the polar angle of the
middle of its tip (degrees), a flank ``"ccw"`` or ``"cw"`` by the side of that angle its contact
point lies on.

Cost: the closing is vectorised over the positions; each place is rated on a piece of each outline
(``PIECE_PITCHES`` either side), about 20 ms a place — seed 004's ring/planet, 360 positions, in
about 8 s on one core. ``tests/test_mesh_cycle.py`` rates a made elliptical pair.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import GeometryError, SpecError
from transplanter.core.tolerances import CONTACT_TOL_MM
from transplanter.proof.mesh_load import MeshContactLoad, _Closing, _Gear, _outline, mesh_contact_load, safety_factors
from transplanter.proof.tooth_stress import STEEL, Elastic, radius_of_curvature

__all__ = ["ContactRating", "MeshCycleLoad", "Peak", "mesh_cycle_load"]

#: positions whose vertex/edge pairs are held at once
CHUNK = 24
#: the outline each side of a contact that its rating is given, in circular pitches of arc length: a
#: flank, the tooth's far flank and the tooth spaces each side take about 2.4 (a tooth of height
#: 2.25 m and pitch π m has ~2.4 π m of outline)
PIECE_PITCHES = 3.5
#: a corner touching a flank whose normal is within this of the corner's own flank's (degrees)
#: rolls on it with that flank's end; beyond, it pokes the flank (an edge contact, no Hertz)
TANGENT_DEG = 3.0


@dataclass(frozen=True)
class ContactRating:
    """One contact place at one position: its ``step``, the ``point`` and the unit ``normal`` (the
    force on gear 1's flank, machine frame, mm), its ``gap`` (mm, 0 for the first contact), each
    gear's tooth (polar angle of its tip middle in the gear frame, degrees) and flank, and the
    rating (:class:`~transplanter.proof.mesh_load.MeshContactLoad`)."""

    step: int
    point: np.ndarray
    normal: np.ndarray
    gap: float
    teeth: tuple[float, float]
    flanks: tuple[str, str]
    load: MeshContactLoad


@dataclass(frozen=True)
class Peak:
    """An extreme over the cycle: ``value`` at position ``step`` (``theta``, ``driver_angle`` of
    gear 0, degrees), at contact ``place``."""

    value: float
    step: int
    theta: float
    driver_angle: float
    place: ContactRating


@dataclass(frozen=True)
class MeshCycleLoad:
    """Per position (n,): the closing ``turn`` of gear 1 (rad, counter-clockwise +), the contact
    places rated, the largest normal ``force`` (N), ``sigma_h`` (MPa), ``sigma_f`` (n, 2: gear 0's
    tooth, gear 1's, MPa) over them (0 where the torque is 0; ``sigma_h`` over the flank contacts,
    NaN where the only places are corners poking a flank: edge contacts, where Hertz does not
    hold); every place in
    ``places``; the extremes (``max_sigma_h`` over the flank contacts, ``max_corner_force`` the edge
    contacts' largest force); the least safety factors against ``material`` (None, and ``note``
    says why, without one; ``note`` also counts the edge contacts)."""

    theta: np.ndarray = field(repr=False)
    turn: np.ndarray = field(repr=False)
    contacts: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    sigma_h: np.ndarray = field(repr=False)
    sigma_f: np.ndarray = field(repr=False)
    places: tuple[ContactRating, ...] = field(repr=False)
    max_sigma_h: Peak | None
    max_sigma_f: tuple[Peak | None, Peak | None]
    max_corner_force: Peak | None
    s_h: float | None
    s_f: tuple[float | None, float | None]
    material: object | None
    note: str


def _array(value, shape: tuple, name: str) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SpecError(f"{name} must be numbers of shape {shape}") from exc
    if a.shape != shape or not np.all(np.isfinite(a)):
        raise SpecError(f"{name} must be finite numbers of shape {shape}, got shape {a.shape}")
    return a


def _places(index: np.ndarray, n: int) -> list[np.ndarray]:
    """Runs of boundary indices (sorted, unique) a few vertices apart at most, wrapping at n."""
    if not len(index):
        return []
    cut = np.nonzero(np.diff(index) > 3)[0] + 1
    runs = np.split(np.arange(len(index)), cut)
    if len(runs) > 1 and index[0] + n - index[-1] <= 3:
        runs = [np.concatenate((runs[-1], runs[0])), *runs[1:-1]]
    return runs


def _tooth(rs, q: np.ndarray) -> tuple[float, str]:
    tip = rs.centre_line[1]
    t = math.atan2(tip[1], tip[0])
    side = math.remainder(math.atan2(q[1], q[0]) - t, 2 * math.pi)
    return math.degrees(t) % 360.0, "ccw" if side > 0 else "cw"


def mesh_cycle_load(
    outlines,
    poses,
    torque,
    *,
    width: float,
    module: float,
    ring: bool = True,
    pressure_angle: float = 20.0,
    material=None,
    theta=None,
    contact_tol: float = CONTACT_TOL_MM,
    limit: float | None = None,
) -> MeshCycleLoad:
    """Load and stresses of the mesh of gear 0 (a ring with ``ring``) and gear 1 over ``n`` positions.

    Parameters
    ----------
    outlines : two (m, 2) arrays
        Each gear's toothed contour in its own frame, its centre the origin, mm (a ring's toothed hole).
    poses : two (centres (n, 2) mm, angles (n,) rad)
        Each gear frame in the machine at each position: ``x_machine = centre + R(angle) x_gear``;
        gear 1 at its designed angle.
    torque : (n,) float
        The torque the mesh puts on gear 1 about its centre, N mm, counter-clockwise +.
    width, module, pressure_angle
        Face width (mm), module (mm), α_n (degrees) of the teeth.
    material : GearMaterial, optional
        For the elastic constants and the safety factors (steel's, and none, without it).
    theta : (n,) float, optional
        The cycle positions (rad) reported with the extremes; default the index.
    contact_tol : float
        The gap (mm) at which a second place counts as in contact (and carries the whole torque).
    limit : float, optional
        The largest closing turn looked at, rad (default ``module`` over gear 1's largest radius).
    """
    g0, g1 = _outline(outlines[0], "outlines[0]", ring), _outline(outlines[1], "outlines[1]", False)
    torque = np.asarray(torque, dtype=float)
    if torque.ndim != 1 or not len(torque) or not np.all(np.isfinite(torque)):
        raise SpecError("torque must be a finite (n,) array of torques on gear 1, N mm")
    n = len(torque)
    (c0, a0), (c1, a1) = (
        (_array(c, (n, 2), f"poses[{j}] centres"), _array(a, (n,), f"poses[{j}] angles"))
        for j, (c, a) in enumerate(poses)
    )
    theta = np.arange(n, dtype=float) if theta is None else _array(theta, (n,), "theta")
    limit = module / float(np.hypot(*g1.T).max()) if limit is None else limit
    sense = -np.sign(torque)  # the load turns gear 1 against the mesh torque until the flanks touch
    elastic = STEEL if material is None else Elastic(material.e, material.nu)
    job = _Job((_Gear(g0, ring), _Gear(g1, False)), ring, width, module, pressure_angle, elastic, theta)
    turn, count = np.zeros(n), np.zeros(n, dtype=int)
    force, sigma_h, sigma_f = np.zeros(n), np.zeros(n), np.zeros((n, 2))
    places: list[ContactRating] = []
    for start in range(0, n, CHUNK):
        ks = np.arange(start, min(n, start + CHUNK))
        live = ks[torque[ks] != 0]
        if not len(live):
            continue
        cl = _Closing(*job.gears, ring, c0[live], a0[live], c1[live], a1[live], contact_tol, limit)
        delta = cl.first_contact(sense[live], limit)
        if not np.all(np.isfinite(delta)):
            k = int(live[np.nonzero(~np.isfinite(delta))[0][0]])
            raise GeometryError(
                f"at position {k} (theta = {math.degrees(theta[k]):.4g} deg) the teeth do not touch within a turn "
                f"of {limit:.4g} rad of gear 1 from its design angle: the gears are not in mesh there"
            )
        turn[live] = delta
        t = cl.touching(delta, contact_tol)
        for j, k in enumerate(live):
            mine = np.nonzero(t["step"] == j)[0]
            order = mine[np.argsort(t["at"][mine], kind="stable")]
            flank, before = [], len(places)
            for run in _places(t["at"][order], len(g1)):
                best = order[run][int(np.argmin(t["gap"][order[run]]))]
                poses_k = ((c0[k], a0[k]), (c1[k], a1[k] + delta[j]))
                rating = _rate(job, k, poses_k, float(torque[k]), t, best, delta[j], contact_tol)
                places.append(rating)
                force[k] = max(force[k], rating.load.force)
                if rating.load.hertz is not None:
                    flank.append(rating.load.hertz.sigma_h)
                sigma_f[k] = np.maximum(sigma_f[k], [rs.sigma_f for rs in rating.load.root])
            count[k] = len(places) - before
            sigma_h[k] = max(flank) if flank else math.nan
    return _summary(theta, a0, turn, count, force, sigma_h, sigma_f, tuple(places), material)


@dataclass(frozen=True)
class _Job:
    gears: tuple
    ring: bool
    width: float
    module: float
    alpha: float
    elastic: Elastic
    theta: np.ndarray


def _corner(gears, t: dict, best: int, tol: float) -> tuple[int, int]:
    """The corner vertex (outline index, -1: none) each gear touches with: the touching vertex is
    one, or the foot on the other's edge lies within ``tol`` of a corner ending that edge."""
    out = [-1, -1]
    own, other = (1, 0) if t["which"][best] == 0 else (0, 1)
    if gears[own].corners[t["vertex"][best]]:
        out[own] = int(t["vertex"][best])
    first, size = int(t["first"][best]), len(gears[other].xy)
    for end, at in zip(t["ends"][:, best], (first, (first + 1) % size), strict=True):
        if end <= tol and gears[other].corners[at]:
            out[other] = at
    return out[0], out[1]


def _corner_radius(gear: _Gear, corner: int, outward: np.ndarray, window: float, internal: bool) -> float:
    """The radius a corner touches with: the radius of the flank ending at it (measured half a
    window in from the corner) where the other flank's normal is that flank's within
    ``TANGENT_DEG`` (the flank's end rolling on the other, as at the ends of the path of contact);
    NaN where it is not (the corner pokes the other flank: an edge contact)."""
    xy, n = gear.xy, len(gear.xy)
    best, along = math.inf, None
    for a, b in ((corner - 1) % n, corner), (corner, (corner + 1) % n):
        t = (xy[b] - xy[a]) / np.linalg.norm(xy[b] - xy[a])
        miss = math.degrees(math.acos(min(1.0, float(np.dot([t[1], -t[0]], outward)))))
        if miss < best:
            best, along = miss, (t if a == corner else -t)
    if best > TANGENT_DEG:
        return math.nan
    q = xy[corner] + 0.5 * window * along
    return radius_of_curvature(gear.piece(q, 20 * window), q, window, inside=not internal)


def _rate(job: _Job, k: int, poses, torque: float, t: dict, best: int, delta: float, tol: float) -> ContactRating:
    """Rate the place whose closest pair is ``best``: its point, and the normal of the edge touched
    oriented as the force on gear 1 (out of gear 0's material, into gear 1's)."""
    d = t["tangent"][best]
    normal = (1.0 if t["which"][best] == 0 else -1.0) * np.array([d[1], -d[0]]) / float(np.linalg.norm(d))
    point = 0.5 * (t["on0"][best] + t["on1"][best]) + poses[1][0]
    corner = _corner(job.gears, t, best, tol)
    pieces, radii, back = [], [None, None], []
    for g, (gear, (c, a)) in enumerate(zip(job.gears, poses, strict=True)):
        back.append(np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]]))
        pieces.append(gear.piece(back[g] @ (point - c), PIECE_PITCHES * math.pi * job.module))
        if corner[g] >= 0:  # the force on gear 1 leaves gear 0's material and enters gear 1's
            outward = back[g] @ (normal if g == 0 else -normal)
            radii[g] = _corner_radius(gear, corner[g], outward, 0.1 * job.module, job.ring and g == 0)
    kw = {"loaded": 1, "width": job.width, "module": job.module, "elastic": (job.elastic, job.elastic)}
    kw.update(internal=(job.ring, False), pressure_angle=job.alpha)
    try:
        try:
            load = mesh_contact_load(tuple(pieces), poses, point, normal, torque, radii=tuple(radii), **kw)
        except GeometryError:
            if max(corner) < 0:
                raise
            # a corner whose flank's end cannot roll on the other flank (that is concave and
            # tighter, a fillet): it pokes it — an edge contact
            radii = tuple(math.nan if corner[g] >= 0 else None for g in (0, 1))
            load = mesh_contact_load(tuple(pieces), poses, point, normal, torque, radii=radii, **kw)
    except GeometryError as exc:
        raise GeometryError(f"at position {k} (theta = {math.degrees(job.theta[k]):.4g} deg): {exc}") from exc
    named = [_tooth(rs, back[g] @ (point - poses[g][0])) for g, rs in enumerate(load.root)]
    teeth, flanks = (named[0][0], named[1][0]), (named[0][1], named[1][1])
    return ContactRating(k, point, normal, float(t["gap"][best]), teeth, flanks, load)


def _peak(pick, theta, a0, places) -> Peak | None:
    if not places:
        return None
    best = max(places, key=pick)
    k = best.step
    return Peak(float(pick(best)), k, math.degrees(theta[k]), math.degrees(a0[k]), best)


def _summary(theta, a0, turn, count, force, sigma_h, sigma_f, places, material) -> MeshCycleLoad:
    flank = [p for p in places if p.load.hertz is not None]
    edge = [p for p in places if p.load.hertz is None]
    ph = _peak(lambda p: p.load.hertz.sigma_h, theta, a0, flank)
    pf = tuple(_peak(lambda p, g=g: p.load.root[g].sigma_f, theta, a0, places) for g in (0, 1))
    pc = _peak(lambda p: p.load.force, theta, a0, edge)
    corner = ""
    if pc is not None:
        radii = pc.place.load.radii
        who = " and ".join(n for n, r in zip(("gear 0's", "gear 1's"), radii, strict=True) if r is None)
        corner = (
            f"; {len(edge)} contact places at {len({p.step for p in edge})} positions are a corner on a flank (an edge "
            f"contact: no Hertz stress, sigma_h NaN there, the extreme is over the flank contacts) — the largest force "
            f"{pc.value:.4g} N at theta {pc.theta:.4g} deg, {who} corner"
        )
    if material is None:
        s_h, s_f, note = None, (None, None), "no gear material given: stresses only, no safety factors"
    elif pf[0] is None:
        s_h, s_f, note = None, (None, None), "no position carries torque: nothing to rate"
    else:
        s_h = None if ph is None else safety_factors(ph.value, pf[0].value, material).s_h
        s_f = tuple(safety_factors(1.0, p.value, material).s_f for p in pf)
        note = (
            f"against {material.name} ({material.grade}, {material.hardness}): S_H = sigma_Hlim/sigma_H, "
            "S_F = sigma_FE/sigma_F with every ISO 6336 life, size and load factor 1; source: " + material.source
        )
    out = (theta, turn, count, force, sigma_h, sigma_f, places, ph, pf, pc, s_h, s_f, material, note + corner)
    return MeshCycleLoad(*out)
