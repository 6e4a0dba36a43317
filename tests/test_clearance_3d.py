"""The clearance proof judges every two bodies that move against each other in 3D (issue 42): the
axial gap between their planes, or their in-plane distance over the continuous cycle; faces that
touch without a declared joint fail the part. A small machine of two plates is built here (no
build of the part scripts); the built machines' records are held to the same rule at the end."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from transplanter.core.errors import SpecError
from transplanter.families.machines.layers import CarrierLayers, Layers
from transplanter.families.machines.record import clearance_row, pairs_record
from transplanter.machine.bodies import (
    AXIAL,
    IN_PLANE,
    JOINT,
    Body,
    Link,
    judge_pairs,
    pairs_to_judge,
    posed,
)
from transplanter.proof.clearance import posed_sections

#: a crank turning once per driver turn about the origin
CRANK = Link("crank", lambda t: (np.zeros_like(t), np.zeros_like(t), np.asarray(t, dtype=float)), 0.0, 1.0)
#: a member that never moves, set at a constant angle (rigid to the frame)
STILL = Link("still", lambda t: (np.zeros_like(t), np.zeros_like(t), np.full_like(t, 0.3)), 0.0, 0.0)
LINKS = {"fixed": Link.fixed(), "crank": CRANK, "still": STILL}
GRID = 2 * math.pi * np.arange(72) / 72


def _machine(crank_z, joints=None, plate=None):
    """A 40 x 10 mm plate on the crank and a fixed plate it sweeps over (faces on ``crank_z``
    against the fixed plate's z 0-5), judged with a 0.5 mm minimum axial gap and 3 mm in-plane."""
    bodies = [
        Body("fixed_plate", shapely.box(20.0, -5.0, 50.0, 5.0), (0.0, 5.0), "fixed"),
        Body("crank_plate", plate if plate is not None else shapely.box(0.0, -5.0, 40.0, 5.0), crank_z, "crank"),
    ]
    pairs = pairs_to_judge(bodies, LINKS, joints or {}, {}, GRID)
    return bodies, judge_pairs(posed(bodies, LINKS), pairs, GRID, 0.5, lambda p: 3.0)


def test_two_plates_whose_faces_touch_fail_naming_both_the_gap_and_the_overlap():
    bodies, (v,) = _machine((5.0, 10.0))
    assert v.kind == IN_PLANE and not v.passed and v.figure == 0.0 and v.minimum == 3.0
    assert "fixed_plate and crank_plate run face to face" in v.problem and "axial gap 0 mm" in v.problem
    # the largest area the faces share (at driver 0 the crank plate lies over 20 mm of the fixed
    # plate's 30: 200 mm²) and where
    assert "overlap up to 200 mm² at driver 0.0 deg" in v.problem and "not a declared joint" in v.problem
    row = clearance_row(v)
    assert row["kind"] == IN_PLANE and row["pass"] is False and row["axial_gap_mm"] == 0.0
    assert row["figure_mm"] == 0.0 and row["minimum_mm"] == 3.0
    assert pairs_record(bodies, [v], 0.5)["failed"] == 1


def test_half_a_millimetre_between_the_planes_passes_on_the_axial_gap():
    _, (v,) = _machine((5.5, 10.0))
    assert v.kind == AXIAL and v.passed and v.figure == pytest.approx(0.5) and not v.problem
    row = clearance_row(v)
    assert (row["kind"], row["figure_mm"], row["minimum_mm"], row["pass"]) == (AXIAL, 0.5, 0.5, True)
    # 0.4 mm is under the minimum: judged in-plane, and it touches
    _, (closer,) = _machine((5.4, 10.0))
    assert closer.kind == IN_PLANE and not closer.passed and "axial gap 0.4 mm (minimum 0.5 mm)" in closer.problem


def test_a_declared_joint_passes_as_a_joint():
    _, (v,) = _machine((5.0, 10.0), joints={frozenset(("fixed_plate", "crank_plate")): "a thrust washer"})
    assert v.kind == JOINT and v.passed and v.minimum is None and v.judged is None
    row = clearance_row(v)
    assert row["joint"] == "a thrust washer" and row["pass"] and row["axial_gap_mm"] == 0.0


def test_bodies_rigid_to_each_other_are_never_judged():
    """Two bodies on one link, or on links whose relative pose never changes (the frame and a
    member held still at an angle), are rigid: no pair, however they overlap; they are listed."""
    square = shapely.box(0.0, 0.0, 10.0, 10.0)
    bodies = [
        Body("a", square, (0.0, 5.0), "crank"),
        Body("b", square, (0.0, 5.0), "crank"),
        Body("c", square, (0.0, 5.0), "fixed"),
        Body("d", square, (0.0, 5.0), "still"),
    ]
    pairs = pairs_to_judge(bodies, LINKS, {}, {}, GRID)
    assert {frozenset((p.a, p.b)) for p in pairs} == {
        frozenset(p) for p in (("a", "c"), ("a", "d"), ("b", "c"), ("b", "d"))
    }
    verdicts = judge_pairs(posed(bodies, LINKS), pairs, GRID, 0.5, lambda p: 3.0)
    assert pairs_record(bodies, verdicts, 0.5)["rigid"] == ["a + b", "c + d"]
    # kept on purpose (a requirement such as the gearbox above the soil), a rigid pair is judged
    kept = pairs_to_judge(bodies, LINKS, {}, {}, GRID, keep=frozenset({frozenset(("c", "d"))}))
    assert frozenset(("c", "d")) in {frozenset((p.a, p.b)) for p in kept}


def test_the_in_plane_bound_still_finds_a_narrow_dip_between_the_samples():
    """A thin blade on the crank passes a fixed pin 0.15 mm away between two samples 45 deg apart
    (the samples see more than 5 mm), in touching planes: the contact is found and fails."""
    blade = shapely.box(0.0, -0.05, 29.75, 0.05)
    pin = shapely.Point(30.0, 0.3).buffer(0.1, quad_segs=64)
    late = Link(
        "late", lambda t: (np.zeros_like(t), np.zeros_like(t), np.asarray(t, dtype=float) + math.pi / 8), 0.0, 1.0
    )
    links = {"fixed": Link.fixed(), "late": late}
    bodies = [Body("pin", pin, (0.0, 5.0), "fixed"), Body("blade", blade, (5.0, 6.0), "late")]
    theta = 2 * math.pi * np.arange(8) / 8
    (v,) = judge_pairs(posed(bodies, links), pairs_to_judge(bodies, links, {}, {}, theta), theta, 0.5, lambda p: 0.2)
    assert v.judged.samples.values.min() > 5.0 and 0.14 < v.figure < 0.16 and not v.passed
    assert "come 0.15" in v.problem and "(in-plane clearance 0.2 mm)" in v.problem


def test_the_stated_minimum_axial_gap_and_the_pivot_end_are_held():
    with pytest.raises(SpecError, match=r"layers\.min_axial_gap = 0\.2"):
        Layers((0, 12), (13, 25), (26, 34), (35, 41), min_axial_gap=0.2)
    planes = dict(
        cam=(0, 12), lever=(13, 19), carrier1=(20, 28), stage23=(30, 40), stage35=(42, 52), sectors=(54, 64),
        carrier2=(66, 74), spurs=(76, 86), arm=(88, 96), claw=(96, 102),
    )  # fmt: skip
    assert CarrierLayers(**planes, min_axial_gap=1.0).pivot_gap == 1.0
    with pytest.raises(SpecError, match=r"layers\.lever = \(13, 19\).*at least 15 mm"):
        CarrierLayers(**planes, min_axial_gap=1.0, pivot_end=2.0)


@pytest.mark.parametrize("family", ["planetary_seed004", "potseedling_seed002"])
def test_every_pair_of_relatively_moving_bodies_has_a_verdict(built, family):
    """In the built machines' records every two bodies are either rigid to each other (one link,
    or links the motion table never moves against each other) or judged with a kind, a figure, a
    minimum and a pass — every judged one passing, every axial gap at least the stated minimum."""
    folder: Path = built / family
    machine = json.loads((folder / "manifest.json").read_text())["parts"]["machine"]["results"]["machine"]
    bodies = machine["bodies"]
    table = np.loadtxt(folder / machine["motion"], delimiter=",", skiprows=1)
    cols = (folder / machine["motion"]).read_text().splitlines()[0].split(",")

    def pose(name):
        i = cols.index(f"{name}.x_mm")
        return table[:, i], table[:, i + 1], np.radians(table[:, i + 2])

    rows = {frozenset(r["bodies"]): r for r in machine["clearances"]}
    rigid = {frozenset(p.split(" + ")) for p in machine["pairs"]["rigid"]}
    gap = machine["min_axial_gap_mm"]
    names = sorted(bodies)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            (xa, ya, aa), (xb, yb, ab) = pose(a), pose(b)
            c, s = np.cos(ab), np.sin(ab)
            rel = (c * (xa - xb) + s * (ya - yb), -s * (xa - xb) + c * (ya - yb), np.angle(np.exp(1j * (aa - ab))))
            moving = max(float(np.ptp(rel[0])), float(np.ptp(rel[1])), float(np.ptp(np.unwrap(rel[2])))) > 1e-4
            key = frozenset((a, b))
            assert (key in rows) != (key in rigid), f"{a} and {b}: judged and rigid, or neither"
            if moving:
                assert key in rows, f"{a} and {b} move against each other and have no verdict"
    for row in machine["clearances"]:
        za, zb = (bodies[n]["z_mm"] for n in row["bodies"])
        assert row["axial_gap_mm"] == pytest.approx(max(za[0], zb[0]) - min(za[1], zb[1]), abs=1e-9)
        assert row["kind"] in ("axial gap", "in-plane", "joint", "working") and row["pass"] is True
        if row["kind"] == "axial gap":
            assert row["figure_mm"] == row["axial_gap_mm"] >= row["minimum_mm"] == gap >= 0.5
        elif row["kind"] == "in-plane":
            assert row["axial_gap_mm"] < gap and row["figure_mm"] == row["min_mm"] >= row["minimum_mm"]
        elif row["kind"] == "joint":
            assert " + ".join(sorted(row["bodies"])) in machine["joined"]
    assert machine["pairs"]["failed"] == 0 and machine["pairs"]["judged"] == len(rows)


def test_a_body_on_a_still_origin_away_from_the_machine_origin_keeps_true_radii():
    """A link whose origin stands still but not at the machine's origin (a rocker about its ground
    pivot, a screw on a bolt circle): the radii ``posed`` hands the search as its floor are about
    the machine's origin, so they hold every posed point — a floor about the link's own origin
    would let the search set aside the interval holding a narrow dip."""
    pivot = (60.0, 20.0)
    rocker = Link("rocker", lambda t: (np.full_like(t, pivot[0]), np.full_like(t, pivot[1]), 0.6 * np.sin(t)), 0.0, 0.6)
    screw = Link("screw", lambda t: (np.full_like(t, -45.0), np.zeros_like(t), np.full_like(t, 0.4)), 0.0, 0.0)
    links = {"fixed": Link.fixed(), "rocker": rocker, "screw": screw}
    bodies = [
        Body("arm", shapely.box(-5.0, -5.0, 50.0, 5.0), (0.0, 5.0), "rocker"),
        Body("head", shapely.Point(0.0, 0.0).buffer(4.0), (0.0, 5.0), "screw"),
    ]
    for name, p in posed(bodies, links).items():
        x, y, a = p.pose(GRID)
        placed = posed_sections(p.section, x, y, a)
        near = min(float(shapely.distance(shapely.Point(0.0, 0.0), q)) for q in placed)
        far = max(float(np.hypot(*shapely.get_coordinates(q).T).max()) for q in placed)
        assert p.radii[0] <= near + 1e-9 and far <= p.radii[1] + 1e-9, (name, p.radii, near, far)
        if name == "head":  # one that does not turn is measured where it stands: its floor is exact
            assert p.radii[0] == pytest.approx(near, abs=1e-6) and p.radii[0] > 30.0
