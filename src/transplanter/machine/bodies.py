"""A machine as bodies in planes, posed over its cycle, and every two that move against each other
judged in 3D.

A **body** is a plane section in its own (DXF) frame, extruded over a z-range across the machine,
carried by a **link** (fixed, or one of the mechanism's moving members) whose pose — frame origin
and angle in the machine frame — is a function of the driver angle with a stated speed bound
(:class:`Link`). Two bodies on one link, or on links whose relative pose does not change over the
cycle, are rigid to each other and never judged. Every other two (:func:`pairs_to_judge`) are
judged in 3D (:func:`judge_pairs`): their **axial gap** — the gap between their z-ranges,
negative where the ranges overlap — passes when it is at least the stated minimum
(``min_axial_gap``); else their in-plane closest approach over the cycle
(:func:`transplanter.proof.clearance.closest_approach`: bounded, not sampled) must keep the
clearance the designer states. A pair whose planes are apart by less than the minimum (or touch)
and whose outlines come within the clearance runs **face to face**: a contact, which fails unless
the design declares it a **joint** (a mesh, a bearing on its shaft and in its bore, a key in its
keyway, a washer between two faces: recorded, not judged). *Working* pairs (a needle in the
seedling box or in the soil: the tool meets its work there) have their figure recorded, not judged.
:class:`PlanetaryMachine` poses seed 004's train from the made parts' meshing."""

from __future__ import annotations

import math
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import shapely

from transplanter.core.errors import SpecError
from transplanter.design.planetary import DifferentialTrain
from transplanter.proof.clearance import (
    CLEARANCE_REL_TOL,
    CLEARANCE_TOL_MM,
    Approach,
    Posed,
    Samples,
    closest_approach,
    overlap_areas,
    posed_sections,
    reach,
    relative,
)

__all__ = [
    "Body",
    "Link",
    "Pair",
    "Judged",
    "Verdict",
    "AXIAL",
    "IN_PLANE",
    "JOINT",
    "WORKING",
    "axial_gap",
    "moving_links",
    "rigid_pairs",
    "judge_pairs",
    "PlanetaryMachine",
    "pairs_to_judge",
    "posed",
    "clearances",
    "motion_rows",
    "tool_phases",
    "work_depth",
    "MOTION_POSITIONS",
]

#: positions of the motion table per cycle (the judge re-poses the bodies from it)
MOTION_POSITIONS = 1440


@dataclass(frozen=True)
class Link:
    """A member's pose over the cycle: ``pose(theta) -> (x, y, angle)`` arrays (mm, rad) of its
    frame in the machine frame, ``theta`` the driver angle (rad); ``speed`` the largest speed of
    its frame origin and ``turn_rate`` of its angle, per rad of driver (bounds, not samples)."""

    name: str
    pose: Callable
    speed: float = 0.0
    turn_rate: float = 0.0
    #: the rigid frames its origin is a fixed point of, ``(frame, x, y)`` mm (what
    #: :class:`~transplanter.proof.clearance.Posed` bounds two bodies' distance by)
    origin_in: tuple[tuple[str, float, float], ...] = ()

    @staticmethod
    def fixed(name: str = "fixed") -> Link:
        return Link(name, Posed.fixed)


@dataclass(frozen=True)
class Body:
    """A body: its section in its frame (mm), the file it is read from, its z-range across the
    machine (mm) and the link that carries it."""

    name: str
    section: shapely.Polygon = field(repr=False)
    z: tuple[float, float]
    link: str
    dxf: str = ""
    #: mounted face down: ``section`` is its DXF's mirrored about the DXF's x-axis
    mirrored: bool = False

    def __post_init__(self) -> None:
        if not (len(self.z) == 2 and self.z[0] < self.z[1]):
            raise SpecError.out_of_range(f"{self.name}: z", self.z, "(z0, z1) mm with z0 < z1")


#: the kinds of verdict a pair of bodies gets (:func:`judge_pairs`)
AXIAL, IN_PLANE, JOINT, WORKING = "axial gap", "in-plane", "joint", "working"
#: two links whose relative pose moves less than this over the cycle (mm, rad) are rigid to each other
RIGID_TOL = 1e-6


@dataclass(frozen=True)
class Pair:
    """Two bodies that move against each other; ``working``: why the tool meets its work there
    (recorded, not judged); ``joint``: the designed contact that joins them (recorded, not judged);
    ``axial_gap``: the gap between their z-ranges, mm (negative: the ranges overlap by that much)."""

    a: str
    b: str
    working: str = ""
    joint: str = ""
    axial_gap: float = -math.inf


@dataclass(frozen=True)
class Judged:
    """A pair's closest approach over the cycle: distance mm (0: they overlap), driver angle deg,
    the bound below which it cannot be, and the per-position distances on the motion grid."""

    pair: Pair
    distance: float
    at_deg: float
    bound: float
    samples: Samples = field(repr=False)  # on the motion grid, measured when asked (``samples.values``)
    #: False: ``distance`` is only a lower bound (a pair settled without measuring, see
    #: :func:`~transplanter.machine.play.clearances_under_play`, or found to a share of its margin,
    #: :func:`clearances`)
    exact: bool = True
    #: when not ``exact`` and measured: the nearest the search found (mm, at ``at_deg``; an upper
    #: bound: a pose's distance on simplified outlines plus their slack): the true
    #: minimum lies between ``distance`` and this
    nearest: float | None = None

    @classmethod
    def of(cls, pair: Pair, found: Approach) -> Judged:
        """``found`` as the pair's figure: its distance if ``exact``, else its bound."""
        if found.exact:
            return cls(pair, found.distance, math.degrees(found.theta), found.bound, found.samples)
        return cls(pair, found.bound, math.degrees(found.theta), found.bound, found.samples, False, found.distance)


@dataclass(frozen=True)
class Verdict:
    """A pair judged in 3D (:func:`judge_pairs`): its ``kind`` (:data:`AXIAL`, :data:`IN_PLANE`,
    :data:`JOINT`, :data:`WORKING`), the ``figure`` it is judged by (mm: the axial gap, or the
    in-plane closest approach over the cycle), the ``minimum`` it must keep (None: not judged),
    whether it passed, its in-plane approach where measured, and why it failed."""

    pair: Pair
    kind: str
    figure: float
    minimum: float | None
    passed: bool
    judged: Judged | None = None
    problem: str = ""


def axial_gap(a: Body, b: Body) -> float:
    """The gap between two bodies' z-ranges, mm: negative where they overlap, 0 where their
    faces touch."""
    return max(a.z[0], b.z[0]) - min(a.z[1], b.z[1])


def moving_links(links: dict[str, Link], theta: np.ndarray) -> Callable[[str, str], bool]:
    """Whether two links move against each other: their relative pose over ``theta`` (rad)
    changes by more than :data:`RIGID_TOL` (two links of one name, or two fixed, never do)."""
    theta = np.asarray(theta, dtype=float)
    poses = {}
    known: dict[frozenset, bool] = {}

    def pose(name: str):
        if name not in poses:
            at = links[name].pose(theta)
            poses[name] = tuple(np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in at)
        return poses[name]

    def moving(la: str, lb: str) -> bool:
        if la == lb:
            return False
        key = frozenset((la, lb))
        if key not in known:
            x, y, angle = relative(pose(la), pose(lb))
            turn = np.angle(np.exp(1j * (angle - angle[0])))
            known[key] = bool(max(np.ptp(x), np.ptp(y), float(np.max(np.abs(turn)))) > RIGID_TOL)
        return known[key]

    return moving


def pairs_to_judge(
    bodies: list[Body],
    links: dict[str, Link],
    joints: dict[frozenset, str],
    working: dict[frozenset, str],
    theta: np.ndarray,
    keep: frozenset = frozenset(),
) -> list[Pair]:
    """Every two bodies whose links move against each other over ``theta`` (:func:`moving_links`),
    every two a joint declares (``joints``: pair of names -> what joins them, e.g. a mesh or a
    bearing) and those in ``keep`` (judged though rigid to each other: a requirement such as the
    gearbox above the soil), each with its axial gap; ``working`` names the pairs where the tool
    meets its work. The others are rigid to each other (:func:`rigid_pairs`)."""
    moving = moving_links(links, theta)
    out = []
    for i, a in enumerate(bodies):
        for b in bodies[i + 1 :]:
            key = frozenset((a.name, b.name))
            if key in joints or key in keep or moving(a.link, b.link):
                out.append(Pair(a.name, b.name, working.get(key, ""), joints.get(key, ""), axial_gap(a, b)))
    return out


def rigid_pairs(bodies: list[Body], pairs: list[Pair]) -> list[tuple[str, str]]:
    """The two bodies of every pair :func:`pairs_to_judge` left out: rigid to each other."""
    judged = {frozenset((p.a, p.b)) for p in pairs}
    return [(a.name, b.name) for i, a in enumerate(bodies) for b in bodies[i + 1 :] if {a.name, b.name} not in judged]


def judge_pairs(
    bodies: dict[str, Posed],
    pairs: list[Pair],
    theta: np.ndarray,
    min_axial_gap: float,
    required: Callable[[Pair], float],
    tol: float = CLEARANCE_TOL_MM,
    stated: Callable[[Pair], str | None] | None = None,
) -> list[Verdict]:
    """Each pair judged in 3D over the cycle sampled by ``theta`` (rad), ``bodies`` as
    :func:`posed` gives them: a joint is recorded (its axial gap the figure); a working pair gets
    its in-plane closest approach, not judged; a pair whose planes are ``min_axial_gap`` (mm) or
    more apart passes on its axial gap; every other must keep ``required(pair)`` mm in-plane
    (:func:`clearances`: bounded between the samples). One that does not, with its planes apart
    by less than the minimum (or touching), runs face to face: its problem names the axial gap
    and the largest area the two outlines share, where, and over how many positions.

    An in-plane pair is found to a share of its margin over ``required(pair)`` (:func:`clearances`)
    but where the record states it: the pair nearest its minimum, the nearest by distance, and the
    nearest of each group ``stated(pair)`` names (an objective's pairs, say), are found exactly
    (:func:`_nearest_exactly`)."""
    measured = [p for p in pairs if not p.joint and (p.working or p.axial_gap < min_axial_gap)]
    keep = {(p.a, p.b): None if p.working else required(p) for p in measured}
    found = {(j.pair.a, j.pair.b): j for j in clearances(bodies, measured, theta, tol, keep)}
    found.update(_nearest_exactly(bodies, found, keep, stated or (lambda p: None), theta, tol))
    out = []
    for p in pairs:
        if p.joint:
            out.append(Verdict(p, JOINT, p.axial_gap, None, True))
            continue
        if p.working:
            j = found[(p.a, p.b)]
            out.append(Verdict(p, WORKING, j.distance, None, True, j))
            continue
        if p.axial_gap >= min_axial_gap:
            out.append(Verdict(p, AXIAL, p.axial_gap, min_axial_gap, True))
            continue
        j, need = found[(p.a, p.b)], required(p)
        problem = ""
        if j.distance < need and p.axial_gap >= 0.0:
            problem = _face_to_face(bodies[p.a], bodies[p.b], p, j, theta, min_axial_gap, need)
        elif j.distance < need:
            problem = (
                f"{p.a} and {p.b} come {j.distance:.4g} mm apart at driver {j.at_deg:.2f} deg "
                f"(clearance required {need:g} mm; their planes overlap {-p.axial_gap:g} mm)"
            )
        out.append(Verdict(p, IN_PLANE, j.distance, need, not problem, j, problem))
    return out


def _nearest_exactly(bodies: dict[str, Posed], found: dict, keep: dict, stated, theta, tol: float) -> dict:
    """Each group's pairs that may be its nearest, measured again exactly. A group is stated by its
    least margin over its minimum: every in-plane pair (by margin, and by distance alone: a
    report's smallest clearance) and each group ``stated`` names. A pair not ``exact`` is measured
    again where its lower bound's margin is within the exact tolerance of the least the group's
    search found (the nearest's exact figure may lie up to that above it)."""
    groups: dict[object, list] = {}
    for key, j in found.items():
        need = keep[key]
        if need is None:  # at its work: not judged
            continue
        groups.setdefault("margin", []).append((key, j, need))
        groups.setdefault("distance", []).append((key, j, 0.0))
        if (named := stated(j.pair)) is not None:
            groups.setdefault(("stated", named), []).append((key, j, need))
    again = set()
    for members in groups.values():
        upper = [j.distance if j.nearest is None else j.nearest for _, j, _ in members]
        k = min(range(len(members)), key=lambda i: upper[i] - members[i][2])
        least = upper[k] - members[k][2] + 1.01 * max(tol, CLEARANCE_REL_TOL * upper[k])
        again |= {key for key, j, less in members if not j.exact and j.distance - less <= least}
    return {(j.pair.a, j.pair.b): j for j in clearances(bodies, [found[k].pair for k in sorted(again)], theta, tol)}


def _face_to_face(a: Posed, b: Posed, p: Pair, j: Judged, theta, min_axial_gap: float, need: float) -> str:
    """What a face-to-face contact is: the axial gap, the largest area the outlines share on the
    ``theta`` positions and where, or how near they come when they only approach."""
    area = overlap_areas(a, b, np.asarray(theta, dtype=float))
    head = f"{p.a} and {p.b} run face to face: axial gap {p.axial_gap:g} mm (minimum {min_axial_gap:g} mm)"
    tail = "a contact that is not a declared joint"
    if area.max() > 0.0:
        k = int(np.argmax(area))
        on = area > 0.0
        deg = np.degrees(np.asarray(theta, dtype=float))
        where = "every position"
        if not on.all():  # from the first position after one without overlap, round the cycle
            order = np.roll(np.arange(len(on)), -int(np.argmin(on)))
            inside = order[on[order]]
            where = f"{int(on.sum())} of {len(on)} positions, driver {deg[inside[0]]:.1f} to {deg[inside[-1]]:.1f} deg"
        return f"{head}, their outlines overlap up to {area[k]:.4g} mm² at driver {deg[k]:.1f} deg (on {where}): {tail}"
    return (
        f"{head}, their outlines come {j.distance:.4g} mm apart at driver {j.at_deg:.2f} deg "
        f"(in-plane clearance {need:g} mm): {tail}"
    )


#: the simpler outlines measured first (``clearance.Posed.levels``), mm from the section
LEVELS_MM = (0.05, 0.005)


def posed(bodies: list[Body], links: dict[str, Link]) -> dict[str, Posed]:
    """Each body on its link, ready to be judged: its speed bound, its simpler outlines
    (Douglas-Peucker keeps vertices of the outline, so each is within its tolerance of the section
    both ways) and, for a body fixed or turning about the origin, the radii its points keep."""
    out = {}
    for body in bodies:
        link = links[body.link]
        levels = tuple((body.section.simplify(tol), tol) for tol in LEVELS_MM)
        radii = None
        if link.speed == 0.0:
            radii = _radii(body.section, link)
        speed = link.speed + link.turn_rate * reach(body.section)
        out[body.name] = Posed(body.section, link.pose, speed, levels, radii, link.origin_in)
    return out


def _radii(section: shapely.Polygon, link: Link) -> tuple[float, float]:
    """Least and largest distance of ``section`` from the machine's origin over the cycle, its link's
    origin standing still: measured where it stands if it does not turn; else its radii about its
    origin widened by that origin's distance from the machine's (the triangle inequality)."""
    x, y, angle = (float(np.asarray(v, dtype=float).reshape(-1)[0]) for v in link.pose(np.zeros(1)))
    if link.turn_rate == 0.0:
        placed = posed_sections(section, x, y, angle)[0]
        return float(shapely.distance(shapely.Point(0.0, 0.0), placed)), reach(placed)
    off = math.hypot(x, y)
    return max(0.0, float(shapely.distance(shapely.Point(0.0, 0.0), section)) - off), reach(section) + off


def clearances(
    bodies: dict[str, Posed],
    pairs: list[Pair],
    theta: np.ndarray,
    tol: float = CLEARANCE_TOL_MM,
    need: dict[tuple[str, str], float | None] | None = None,
) -> list[Judged]:
    """Each pair's closest approach over the cycle sampled by ``theta`` (rad; refined between
    the samples under the speed bounds, :func:`clearance.closest_approach`); ``bodies`` as
    :func:`posed` gives them. A pair with a clearance to keep (``need[(a, b)]``, mm) is found to a
    share of its margin over it: where that is wider than the exact tolerance, its figure is the
    proved lower bound, not ``exact``, and the nearest the search found its ``nearest``."""

    def judge(p: Pair) -> Judged:
        return Judged.of(p, closest_approach(bodies[p.a], bodies[p.b], theta, tol, (need or {}).get((p.a, p.b))))

    # two at a time: GEOS and numpy release the GIL for most of a pair's measuring
    with ThreadPoolExecutor(max_workers=2) as pool:
        return list(pool.map(judge, pairs))


def work_depth(tool: Body, work: Body, link: Link, theta: np.ndarray, tip, back) -> tuple[float, float, float]:
    """How far from its ``tip`` a tool (a needle, on ``link``) enters a fixed ``work`` body: the
    farthest point of the tool inside the work, measured along the tool (``back`` → ``tip``, its
    frame, mm) from the tip, at ``theta``. Returns (deepest mm, driver angle rad, at most mm — the
    deepest plus what it can gain between the positions: its points' speed bound times half a step,
    ``theta`` uniform over a turn)."""
    tip, back = np.asarray(tip, dtype=float), np.asarray(back, dtype=float)
    u = (tip - back) / np.linalg.norm(tip - back)
    pose = tuple(np.broadcast_to(v, theta.shape) for v in link.pose(theta))
    # the work in the tool's frame at each position (it is fixed in the machine)
    local = posed_sections(work.section, *relative(Posed.fixed(theta), pose))
    depth = np.zeros(len(theta))
    for k, g in enumerate(shapely.intersection(tool.section, local)):
        pts = shapely.get_coordinates(g)
        if len(pts):
            depth[k] = float(np.max((tip - pts) @ u))
    k = int(np.argmax(depth))
    speed = link.speed + link.turn_rate * float(np.linalg.norm(tip))
    return float(depth[k]), float(theta[k]), float(depth[k]) + speed * math.pi / len(theta)


def tool_phases(tip: np.ndarray, pick, plant, names: tuple[str, str, str, str]) -> list[str]:
    """A tool's phase at each position of its ``tip`` path (n, 2): inside ``pick`` (the seedling
    box: ``names[0]``), inside ``plant`` (the soil: ``names[2]``), and between them ``names[1]``
    (from pick to plant) or ``names[3]`` (back from plant to pick)."""
    inside = shapely.contains_xy(pick, tip[:, 0], tip[:, 1])
    below = shapely.contains_xy(plant, tip[:, 0], tip[:, 1])
    event = np.where(inside, 1, np.where(below, 2, 0))
    if not event.any():
        return [names[1]] * len(tip)
    last = int(event[np.flatnonzero(event)[-1]])  # the event before the first position
    out = []
    for e in event:
        last = int(e) or last
        out.append(names[0] if e == 1 else names[2] if e == 2 else names[1] if last == 1 else names[3])
    return out


def motion_rows(bodies: list[Body], links: dict[str, Link], theta: np.ndarray) -> tuple[list[str], list[list[str]]]:
    """The motion table a judge re-poses the bodies from: ``driver_deg`` and for each body
    ``NAME.x_mm``, ``NAME.y_mm``, ``NAME.angle_deg`` (its DXF frame in the machine frame)."""
    header = ["driver_deg"]
    columns = [np.degrees(theta)]
    for b in bodies:
        x, y, a = (np.broadcast_to(v, theta.shape) for v in links[b.link].pose(theta))
        header += [f"{b.name}.x_mm", f"{b.name}.y_mm", f"{b.name}.angle_deg"]
        columns += [x, y, np.degrees(a)]
    table = np.stack(columns, axis=1)
    return header, [[f"{v:.6f}" for v in row] for row in table]


@dataclass(frozen=True)
class PlanetaryMachine:
    """Seed 004's train as moving links: ``made`` the ``DifferentialTrain`` rebuilt from the parts'
    meshing (its pair a ``train_rebuild`` pair whose planet angle carries the measured error);
    ``error_slope`` the largest rate of that error per rad of ring turn (from its samples).

    The driver is the carrier: θ its clockwise turn from the start (rad). The machine frame is the
    train's (seed 004 eqs 3-10: O at the origin, y up); the ring's DXF frame has arm I's carrier line
    on +x at the start, so the ring's angle is ``φH0 - (ω1/ω2) θ``, the carrier's ``φH0 - θ`` (its
    first planet shaft on +x is arm I's), planet k's centre ``|OO1| e(φH0 - θ - 2πk/N)`` and its angle
    the rebuilt train's planet attitude."""

    made: DifferentialTrain
    error_slope: float = 0.0

    @cached_property
    def links(self) -> dict[str, Link]:
        """The ring, the carrier, each planet (``planet.k``, carrying what is fixed to it) and
        ``fixed``, with their speed bounds."""
        tr = self.made
        w, start, a = tr.omega_ratio, tr.carrier_start, tr.pair.centre_distance
        phi = np.linspace(0.0, 2 * math.pi, 20_000, endpoint=False)
        # the planet turns at -1 + (1 - ω) (dψ/dφ + error slope) per rad of carrier; dψ/dφ, the pair's
        # ratio sampled 20 000 times a turn, cannot exceed two samples by more than their largest step
        ratio = np.asarray(tr.pair.ratio(phi), dtype=float)
        between = float(np.max(np.abs(np.diff(np.append(ratio, ratio[0])))))
        rate = float(np.max(np.abs(-1.0 + (1.0 - w) * ratio))) + abs(1.0 - w) * (between + self.error_slope)
        out = {
            "fixed": Link.fixed(),
            "ring": Link("ring", lambda t: _turning(t, start - w * np.asarray(t)), 0.0, abs(w)),
            "carrier": Link("carrier", lambda t: _turning(t, start - np.asarray(t)), 0.0, 1.0),
        }
        for k in range(tr.planets):
            out[f"planet.{k + 1}"] = Link(f"planet.{k + 1}", lambda t, k=k: self._planet(t, k), a, rate)
        return out

    def _planet(self, theta, k: int):
        s = self.made.state(np.atleast_1d(np.asarray(theta, dtype=float)), k)
        return s.centre[:, 0], s.centre[:, 1], s.planet_angle

    def tips(self, theta) -> list[np.ndarray]:
        """Each arm's needle tip over ``theta``, (n, 2) mm."""
        return [self.made.state(theta, k).tip for k in range(self.made.planets)]


def _turning(theta, angle):
    x, y, z = Posed.fixed(theta)
    return x, y, np.asarray(angle, dtype=float) + z
