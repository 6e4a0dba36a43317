"""A third machine from the generic model (issue 42): seed 000's planting four-bar (mechanism B of
Table 1) posed as links and bodies — a kinematics function and a list of bodies, no study class —
judged in 3D by :mod:`transplanter.machine.bodies` and listed by :mod:`transplanter.shop.bom`.

The stack across the machine (z, mm; 6 mm plates, our choice as in ``parts/fourbar_seed000.py``),
back to front: frame plate 0-6, crank 7-13, coupler 14-20, rocker 21-27 — 1 mm between every two
members that move against each other. The crank is keyed (DIN 6885-1) to a Ø12 drive shaft running
in an ISO 15 bearing in the frame, held back by a DIN 471 ring. Each pin joint (B crank-coupler,
C coupler-rocker, O4 frame-rocker) is an ISO 4762 M8 cap screw threaded into one member (tap drill
6.8 mm) whose shank carries an ISO 15 bearing pressed into the other member and whose head holds
the bearing's inner ring; the catalogue has no shoulder screw, so the bearing sits on the screw's
thread (a simplification stated here, not a recommendation). The pin at O4 crosses the crank's and
the coupler's planes: those pairs are judged in-plane over the cycle. The two members of each pin
joint (the pin and its head against the other member's plate) are declared joined, not judged:
they turn about one axis, and :func:`test_the_revolute_joints_are_concentric` holds that and
measures their constant distance.

Speed bounds are derived from the kinematics: per rad of crank, the coupler's origin B moves at the
crank length exactly; the coupler's and rocker's turn rates are the largest |dθ/dθ2| of the closed
form (``FourBar.solve`` with ω2 = 1) on 4096 crank positions, plus the largest |d²θ/dθ2²| times half
a step (what the rate can gain between two samples), times a safety factor of 1.05.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
import shapely

from transplanter.core.errors import SpecError
from transplanter.design.linkage.fourbar import Link as Member
from transplanter.families.machines.assembly import BoughtBody, bought_parts
from transplanter.families.machines.bill import machine_bom
from transplanter.machine.bodies import AXIAL, IN_PLANE, JOINT, Body, Link, judge_pairs, pairs_to_judge, posed
from transplanter.proof.clearance import posed_sections
from transplanter.shop.catalogue import bearing_for, circlip_for_shaft, fit, key_for, screw
from transplanter.shop.catalogue.fasteners import screw_lengths
from transplanter.shop.solids import circle_polygon

PLATE = 6.0  # mm, the plates' thickness (parts/fourbar_seed000.py)
MIN_AXIAL_GAP = 1.0  # mm, between the planes of two members that move against each other
IN_PLANE_MM = 1.0  # mm, the clearance two bodies whose planes overlap must keep
#: the judge finds each in-plane closest approach to within this (its figure an upper bound of the
#: true one), so a pair must show IN_PLANE_MM + JUDGE_TOL_MM: coarser than the built machines' wire
#: tolerance, because the bound between samples is each body's own speed, not the pair's relative
#: one, and pairs whose distance never changes (the pins at B and C, a coupler length apart) then
#: take ~1 s each at the wire's tolerance
JUDGE_TOL_MM = 0.25
SAFETY = 1.05  # on the turn-rate bounds (module docstring)
BOUND_GRID = 4096  # crank positions the turn-rate bounds are taken over
POSITIONS = 120  # driver positions the judge samples (it bounds the distance between them)
#: the z-range of each plate, mm
Z = {"frame": (0.0, 6.0), "crank": (7.0, 13.0), "coupler": (14.0, 20.0), "rocker": (21.0, 27.0)}
SHAFT_D, PIN = 12.0, "M8"
TAP_DRILL_M8 = 6.8  # mm, ISO 2306 / DIN 336 tap drill
WALL = 5.0  # mm, round a bearing's bore; a tapped or keyed boss as parts/fourbar_seed000.py (Ø20, Ø28)
NOSE = 5.0  # mm, finger tip radius
#: the load case the bearings are chosen for (our statement): the crank's 240 r/min, 200 N radial
SPEED_RPM, RADIAL_N = 240.0, 200.0


def _kinematics(arm):
    """The links of ``arm``: each member's pose over the driver angle θ (the crank's turn from its
    angle reference, in the arm's sense), with the speed bounds the module docstring states."""
    fb = arm.linkage
    sense = 1.0 if arm.crank_speed > 0 else -1.0

    def solve(theta):
        t = np.asarray(theta, dtype=float)
        return t.shape, fb.solve(arm.angle_reference + sense * t.ravel())

    def crank(theta):
        shape, m = solve(theta)
        z = np.zeros(shape)
        return z, z, m.theta[Member.CRANK].reshape(shape)

    def coupler(theta):
        shape, m = solve(theta)
        b = m.joints()["B"]
        return b[:, 0].reshape(shape), b[:, 1].reshape(shape), m.theta[Member.COUPLER].reshape(shape)

    def rocker(theta):
        shape, m = solve(theta)
        o4 = np.broadcast_to(np.asarray(fb.rocker_pivot, dtype=float), (*shape, 2))
        return o4[..., 0], o4[..., 1], m.theta[Member.ROCKER].reshape(shape)

    grid = 2 * math.pi * np.arange(BOUND_GRID) / BOUND_GRID
    m = fb.solve(grid, 1.0, 0.0)  # ω2 = 1: the rates are per rad of crank

    def rate(member):
        return SAFETY * (np.abs(m.omega[member]).max() + np.abs(m.alpha[member]).max() * math.pi / BOUND_GRID)

    # the rocker turns about O4, which never moves: its origin speed is 0 (bodies.posed widens its
    # radii about O4 by |O2 O4| for the floor closest_approach takes about the machine's origin)
    return {
        "fixed": Link.fixed(),
        "crank": Link("crank", crank, 0.0, 1.0),
        "coupler": Link("coupler", coupler, fb.crank, float(rate(Member.COUPLER))),
        "rocker": Link("rocker", rocker, 0.0, float(rate(Member.ROCKER))),
    }


def _plate(bosses, holes, finger=None):
    """A plate: the hull of its bosses ``(x, y, diameter)`` (and of a finger: a boss and the nose
    disc) less its holes ``(x, y, diameter)``, in its link's frame, mm."""
    body = shapely.convex_hull(shapely.union_all([circle_polygon(x, y, d / 2) for x, y, d in bosses]))
    if finger is not None:
        body = shapely.union(body, shapely.convex_hull(shapely.union_all(finger)))
    return body.difference(shapely.union_all([circle_polygon(x, y, d / 2) for x, y, d in holes]))


def _screw(length):
    """The ISO 4762 M8 screw of a standard ``length``, or None where M8 has none that long."""
    try:
        return screw(PIN, length)
    except SpecError:
        return None


def _ring(x, y, inner, outer):
    return circle_polygon(x, y, outer / 2).difference(circle_polygon(x, y, inner / 2))


def _machine(arm, z=None):
    """The bodies, links, joints, the part each body belongs to (``made:stem`` or the bought body),
    the bought bodies and each pin joint's axis (carrier link and point, holder link and point, the
    holder's plate) of ``arm`` on the stack ``z`` (default :data:`Z`)."""
    z = {**Z, **(z or {})}
    fb = arm.linkage
    o4 = tuple(float(v) for v in np.subtract(fb.rocker_pivot, fb.origin))
    pin_bearing = bearing_for(8.0, SPEED_RPM, RADIAL_N)
    shaft_bearing = bearing_for(SHAFT_D, SPEED_RPM, RADIAL_N)
    dp, ds = pin_bearing.D, shaft_bearing.D
    key = key_for(SHAFT_D, PLATE)
    ring = circlip_for_shaft(SHAFT_D)
    head = screw(PIN, 12.0)  # the head's size is the size's
    tip = arm.tip
    # where each pin joint sits: (label, carrier link + frame point, bearing link + frame point)
    pins = {
        "B": ("crank", (fb.crank, 0.0), "coupler", (0.0, 0.0)),
        "C": ("coupler", (fb.coupler, 0.0), "rocker", (fb.rocker, 0.0)),
        "O4": ("fixed", o4, "rocker", (0.0, 0.0)),
    }
    bodies = [
        Body("frame", _plate([(0, 0, ds + 2 * WALL), (*o4, 20.0)], [(0, 0, ds), (*o4, TAP_DRILL_M8)]),
             z["frame"], "fixed"),
        Body("crank", _plate([(0, 0, 28.0), (fb.crank, 0, 20.0)], [(0, 0, SHAFT_D), (fb.crank, 0, TAP_DRILL_M8)]),
             z["crank"], "crank"),
        Body("coupler", _plate([(0, 0, dp + 2 * WALL), (fb.coupler, 0, 20.0)],
                               [(0, 0, dp), (fb.coupler, 0, TAP_DRILL_M8)],
                               finger=[circle_polygon(0, 0, dp / 2 + WALL), circle_polygon(*tip, NOSE)]),
             z["coupler"], "coupler"),
        Body("rocker", _plate([(0, 0, dp + 2 * WALL), (fb.rocker, 0, dp + 2 * WALL)], [(0, 0, dp), (fb.rocker, 0, dp)]),
             z["rocker"], "rocker"),
        # the drive shaft, from 10 mm behind the frame to the crank's front face
        Body("drive_shaft", circle_polygon(0, 0, SHAFT_D / 2), (-10.0, Z["crank"][1]), "crank"),
        Body("bearing_O2", _ring(0, 0, SHAFT_D, ds), (0.0, shaft_bearing.B), "fixed"),
        Body("ring_O2", _ring(0, 0, ring.groove_diameter, ring.groove_diameter + 2 * ring.lug), (-0.05 - ring.s, -0.05),
             "crank"),
        # the key on the crank's -x side, in its keyway across the crank's hub
        Body("key_O2", shapely.box(-(SHAFT_D / 2 - key.t1 + key.h), -key.b / 2, -(SHAFT_D / 2 - key.t1), key.b / 2),
             z["crank"], "crank"),
    ]  # fmt: skip
    joints = {
        frozenset(("bearing_O2", "frame")): f"bearing {shaft_bearing.designation}: in its bore ({fit(ds, 'H7').text})",
        frozenset(("bearing_O2", "drive_shaft")): f"bearing: on its shaft ({fit(SHAFT_D, 'k6').text})",
        frozenset(("ring_O2", "bearing_O2")): f"retaining ring {ring.designation}: against the inner ring",
        frozenset(("key_O2", "crank")): f"key {key.designation}: in the crank's keyway",
        frozenset(("key_O2", "drive_shaft")): f"key {key.designation}: in the shaft's keyway",
    }
    part_of = {b.name: f"made:{b.name}" for b in bodies[:5]}
    axes = {}
    bought = [
        BoughtBody("bearing_O2", shaft_bearing, "fixed", z=0.0),
        BoughtBody("ring_O2", ring, "crank", z=-0.05 - ring.s),
        BoughtBody("key_O2", key, "crank", z=z["crank"][0]),
    ]
    for label, (carrier, (xc, yc), holder, (xh, yh)) in pins.items():
        zc, zh = z[carrier if carrier != "fixed" else "frame"], z[holder]
        front = max(zc[1], zh[1])
        # the screw: the longest standard length that ends inside the member it is threaded into
        fastener = max((_screw(length) for length in screw_lengths() if front - length >= zc[0]),
                       key=lambda s: 0.0 if s is None else s.length)  # fmt: skip
        length = fastener.length
        engaged = zc[1] - (front - length)
        assert engaged >= 0.5 * fastener.d, f"pin {label}: {fastener.designation} engages {engaged:g} mm of thread"
        bodies += [
            Body(f"pin_{label}", circle_polygon(xc, yc, fastener.d / 2), (front - length, front), carrier),
            Body(f"head_{label}", circle_polygon(xc, yc, head.head_diameter / 2), (front, front + head.head_height),
                 carrier),
            Body(f"bearing_{label}", _ring(xh, yh, pin_bearing.d, dp), (zh[1] - pin_bearing.B, zh[1]), holder),
        ]  # fmt: skip
        bought += [
            BoughtBody(f"pin_{label}", fastener, carrier, xc, yc, front, flip=True),
            BoughtBody(f"bearing_{label}", pin_bearing, holder, xh, yh, zh[1] - pin_bearing.B),
        ]
        part_of |= {
            f"pin_{label}": f"pin_{label}",
            f"head_{label}": f"pin_{label}",
            f"bearing_{label}": f"bearing_{label}",
        }
        bearing, plate = f"bearing {pin_bearing.designation}", holder if holder != "fixed" else "frame"
        joints |= {
            frozenset((f"bearing_{label}", plate)): f"{bearing}: in its bore ({fit(dp, 'H7').text})",
            frozenset((f"bearing_{label}", f"pin_{label}")): f"{bearing}: on its pin ({fastener.designation})",
            frozenset((f"bearing_{label}", f"head_{label}")): "the screw's head: against the bearing's inner ring",
            # the two members of the revolute joint: concentric about its axis, so their distance
            # never changes (held in test_the_revolute_joints_are_concentric, not by the judge)
            frozenset((f"pin_{label}", plate)): f"joint {label}: the pin through the {plate}'s bearing bore",
            frozenset((f"head_{label}", plate)): f"joint {label}: the screw's head over the {plate}'s bearing bore",
        }
        axes[label] = (carrier, (xc, yc), holder, (xh, yh), plate)
    part_of |= {"bearing_O2": "bearing_O2", "ring_O2": "ring_O2", "key_O2": "key_O2"}
    return bodies, _kinematics(arm), joints, part_of, bought, axes


@pytest.fixture(scope="module")
def arm(seed000_arms):
    return seed000_arms["B"]


def _judge(bodies, links, joints, only=None):
    """Every pair of ``bodies`` that moves against another or is joined, judged in 3D over
    :data:`POSITIONS` driver positions (those with a body named in ``only``, if given)."""
    theta = 2 * math.pi * np.arange(POSITIONS) / POSITIONS
    pairs = pairs_to_judge(bodies, links, joints, {}, theta)
    if only is not None:
        pairs = [p for p in pairs if {p.a, p.b} & set(only)]
    required = IN_PLANE_MM + JUDGE_TOL_MM
    return judge_pairs(posed(bodies, links), pairs, theta, MIN_AXIAL_GAP, lambda p: required, JUDGE_TOL_MM)


@pytest.fixture(scope="module")
def judged(arm):
    start = time.perf_counter()
    bodies, links, joints, _, _, _ = _machine(arm)
    verdicts = _judge(bodies, links, joints)
    return bodies, verdicts, time.perf_counter() - start


def test_the_speed_bounds_hold_on_a_finer_grid(arm):
    """The stated bounds are bounds: no member's origin or angle moves faster per rad of driver on
    a grid four times finer than the one they were taken on (finite differences)."""
    links = _kinematics(arm)
    t = 2 * math.pi * np.arange(4 * BOUND_GRID + 1) / (4 * BOUND_GRID)
    for name in ("crank", "coupler", "rocker"):
        x, y, a = (np.asarray(v, dtype=float) for v in links[name].pose(t))
        h = np.diff(t)
        speed = float(np.max(np.hypot(np.diff(x), np.diff(y)) / h))
        turn = float(np.max(np.abs(np.diff(np.unwrap(a))) / h))
        link = links[name]
        assert speed <= link.speed + 1e-6, f"{name}: origin speed {speed:.6g} > bound {link.speed:.6g} mm/rad"
        assert turn <= link.turn_rate + 1e-9, f"{name}: turn rate {turn:.6g} > bound {link.turn_rate:.6g}"
    assert links["coupler"].turn_rate < 1.0 and links["rocker"].turn_rate < 1.0  # a crank-rocker: slower than the crank


def test_every_pair_that_moves_against_another_passes_in_3d(judged):
    bodies, verdicts, seconds = judged
    failed = [v.problem for v in verdicts if not v.passed]
    assert not failed, "\n".join(failed)
    kinds = {k: [v for v in verdicts if v.kind == k] for k in (AXIAL, IN_PLANE, JOINT)}
    axial = min(v.figure for v in kinds[AXIAL])
    plane = min(kinds[IN_PLANE], key=lambda v: v.figure)
    summary = (
        f"{len(verdicts)} pairs judged ({len(kinds[AXIAL])} on the axial gap, {len(kinds[IN_PLANE])} in-plane, "
        f"{len(kinds[JOINT])} joints) in {seconds:.2f} s; smallest axial gap {axial:g} mm; smallest in-plane "
        f"clearance {plane.figure:.4g} mm ({plane.pair.a} and {plane.pair.b} at driver {plane.judged.at_deg:.1f} deg)"
    )
    print(summary)
    assert axial >= MIN_AXIAL_GAP, summary
    assert all(v.figure >= IN_PLANE_MM + JUDGE_TOL_MM for v in kinds[IN_PLANE]), summary
    # the plates: every two in distinct planes at least the minimum apart
    for v in verdicts:
        plates = {v.pair.a, v.pair.b}
        if plates <= set(Z):
            assert v.kind == AXIAL and v.figure >= MIN_AXIAL_GAP, f"{plates}: {v.kind} {v.figure:g} mm"
    # the pin at O4 crosses the crank's and the coupler's planes: judged in-plane, with room
    crossing = {frozenset((v.pair.a, v.pair.b)): v for v in kinds[IN_PLANE]}
    for other in ("crank", "coupler"):
        v = crossing[frozenset(("pin_O4", other))]
        assert v.figure >= IN_PLANE_MM, f"pin_O4 and {other}: {v.figure:.4g} mm in-plane"


def test_the_revolute_joints_are_concentric(arm):
    """What the joints declare without judging is true: each pin's axis is one point of the machine
    in both members' frames at every position (the joint's members only turn about it), so the pin
    and the screw's head keep one distance to the other member's bearing bore — measured here at
    every position, and at least the in-plane clearance."""
    bodies, links, _, _, _, axes = _machine(arm)
    theta = 2 * math.pi * np.arange(POSITIONS) / POSITIONS
    by_name = {b.name: b for b in bodies}
    for label, (carrier, (xc, yc), holder, (xh, yh), plate) in axes.items():
        where = []
        for link, (u, v) in ((carrier, (xc, yc)), (holder, (xh, yh))):
            x, y, a = (np.broadcast_to(np.asarray(w, dtype=float), theta.shape) for w in links[link].pose(theta))
            where.append(np.stack([x + np.cos(a) * u - np.sin(a) * v, y + np.sin(a) * u + np.cos(a) * v], axis=1))
        drift = float(np.max(np.linalg.norm(where[0] - where[1], axis=1)))
        assert drift < 1e-9, f"joint {label}: the axis drifts {drift:.3g} mm between {carrier} and {holder}"
        for part in (f"pin_{label}", f"head_{label}"):
            a, b = posed([by_name[part], by_name[plate]], links).values()
            gaps = [
                shapely.distance(posed_sections(a.section, *(np.atleast_1d(w[k]) for w in a.pose(theta)))[0],
                                 posed_sections(b.section, *(np.atleast_1d(w[k]) for w in b.pose(theta)))[0])
                for k in range(0, POSITIONS, 10)
            ]  # fmt: skip
            assert np.ptp(gaps) < 1e-3 and min(gaps) >= IN_PLANE_MM, (
                f"{part} and {plate}: {min(gaps):.4g}-{max(gaps):.4g} mm"
            )


def test_a_plate_moved_onto_its_neighbours_plane_fails_naming_both(arm):
    """The proof can fail: the crank put on the frame's front face (axial gap 0) runs face to face
    with the frame plate over its hub."""
    bodies, links, joints, *_ = _machine(arm, {"crank": (6.0, 12.0)})
    verdicts = _judge(bodies, links, joints, only=("crank",))
    (v,) = [v for v in verdicts if {v.pair.a, v.pair.b} == {"frame", "crank"}]
    assert not v.passed and v.kind == IN_PLANE, f"frame and crank: {v.kind} {v.figure:g} mm"
    assert "frame and crank run face to face: axial gap 0 mm (minimum 1 mm)" in v.problem, v.problem
    assert "not a declared joint" in v.problem, v.problem


def test_every_body_is_a_made_part_or_a_bought_item_one_to_one(arm):
    """The bill of materials of the same bodies (``families.machines.bill.machine_bom``, checked
    one to one against the made files): each body belongs to exactly one part, each made part is an
    item of its files, each bought body is counted in the item of its designation."""
    bodies, _, _, part_of, bought, _ = _machine(arm)
    assert sorted(part_of) == sorted(b.name for b in bodies)
    made = sorted({p.split(":", 1)[1] for p in part_of.values() if p.startswith("made:")})
    by_name = {b.name: b for b in bodies}
    records = {
        stem: {
            "stem": stem,
            "material": "C45" if stem == "drive_shaft" else "S235JR",
            "quantity": 1,
            "solid_volume_mm3": by_name[stem].section.area * (by_name[stem].z[1] - by_name[stem].z[0]),
            "dxf_R2000": "written",
        }
        for stem in made
    }
    files = [f"{stem}.dxf" for stem in made]
    bom = machine_bom("fourbar_seed000_B", files, records, bought_parts(bought))
    rows = bom.rows()
    table = "\n".join(", ".join(r) for r in rows)
    print(table)
    assert [i.name for i in bom.items if i.made] == made, table
    # each bought body is in its item, counted; every bought item is some bodies'
    count: dict[str, int] = {}
    for b in bought:
        assert part_of[b.name] == b.name, f"{b.name} is a bought body and a made one"
        count[b.key()] = count.get(b.key(), 0) + 1
    listed = {i.key: i.quantity for i in bom.items if not i.made}
    assert listed == count, table
    assert not bom.problems(files), table
    assert all(i.designation and i.standard for i in bom.items if not i.made), table
    assert set(part_of.values()) == {f"made:{s}" for s in made} | {b.name for b in bought}
    assert len(bom.items) == len(made) + len(count), table
