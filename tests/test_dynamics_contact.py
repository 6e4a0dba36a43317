"""The machine under load (issue 44): a cam on its follower's roller (:class:`Contact`) and circular
gears' pitch point on their line of centres (``Mesh.fraction``) in :mod:`transplanter.machine.dynamics`."""

import math

import numpy as np
import pytest

from transplanter.core.errors import GeometryError, SpecError
from transplanter.machine.bodies import Link
from transplanter.machine.dynamics import Contact, Drive, Lump, Machine, Mesh, Pin, solve

E, R, ROLLER, ARM, PIVOT = 12.0, 40.0, 8.0, 70.0, (30.0, 80.0)


def _roller_centre(t):
    """The roller's centre (n, 2): ARM from the pivot and R + ROLLER from the eccentric disc's centre."""
    d = E * np.stack([np.cos(t), np.sin(t)], axis=1)
    p = np.asarray(PIVOT)
    v = d - p
    dist = np.linalg.norm(v, axis=1)
    along = (ARM**2 - (R + ROLLER) ** 2 + dist**2) / (2 * dist)
    across = np.sqrt(ARM**2 - along**2)
    u = v / dist[:, None]
    return p + along[:, None] * u + across[:, None] * np.stack([-u[:, 1], u[:, 0]], axis=1), d


def _cam_machine() -> Machine:
    t0 = lambda t: np.asarray(t, dtype=float)  # noqa: E731
    cam = Link("cam", lambda t: (np.zeros_like(t0(t)), np.zeros_like(t0(t)), t0(t)))

    def lever_pose(t):
        c, _ = _roller_centre(np.atleast_1d(t0(t)))
        a = np.arctan2(c[:, 1] - PIVOT[1], c[:, 0] - PIVOT[0])
        return np.full_like(a, PIVOT[0]), np.full_like(a, PIVOT[1]), a

    lever = Link("lever", lever_pose)
    lumps = {
        "cam": (Lump(0.8, (E, 0.0, 5.0), 640.0),),
        "lever": (Lump(0.3, (ARM / 2, 4.0, 12.0), 150.0), Lump(0.02, (ARM, 0.0, 5.0), 0.6)),
    }
    pins = (Pin("cam shaft", "fixed", "cam", (0.0, 20.0)), Pin("lever pivot", "fixed", "lever", (0.0, 20.0)))
    contact = Contact("cam on roller", "cam", "lever", 5.0, (ARM, 0.0))
    return Machine(
        {"fixed": Link.fixed(), "cam": cam, "lever": lever},
        lumps,
        pins,
        drives=(Drive("motor", "cam"),),
        contacts=(contact,),
    )


def test_a_cam_on_a_roller_does_no_work_and_pushes_along_the_discs_normal():
    """An eccentric disc on an oscillating roller lever at 300 r/min: Newton-Euler's drive power is
    virtual power's energy rate (the contact does no work), and the contact's line is the disc's
    normal through the roller's centre, away from the cam's axis."""
    theta = 2 * math.pi * np.arange(48) / 48
    loads = solve(_cam_machine(), theta, speed=10 * math.pi)
    assert loads.power_error < 1e-8
    centre, disc = _roller_centre(theta)
    normal = (centre - disc) / np.linalg.norm(centre - disc, axis=1)[:, None]
    assert np.max(np.abs(loads.contact_line[:, 0] - normal)) < 1e-7
    # the lever's moment about its pivot: the contact's alone turns it (its own inertia and weight aside)
    assert loads.contact.shape == (48, 1) and np.ptp(loads.contact[:, 0]) > 1.0


def test_circular_gears_pitch_point_on_the_line_of_centres_is_the_instant_centres():
    """Two equal spur gears on the frame, one driven: the pitch point halfway (``fraction``) gives the
    instant centre's loads; on a turning carrier where they do not turn against each other only the
    fraction is defined."""
    t0 = lambda t: np.asarray(t, dtype=float)  # noqa: E731
    a = Link("a", lambda t: (np.zeros_like(t0(t)), np.zeros_like(t0(t)), t0(t)))
    b = Link("b", lambda t: (np.full_like(t0(t), 60.0), np.zeros_like(t0(t)), -t0(t)))
    lumps = {"a": (Lump(0.5, (3.0, 0.0, 0.0), 200.0),), "b": (Lump(0.5, (0.0, 4.0, 0.0), 200.0),)}
    pins = (Pin("A", "fixed", "a", (0.0, 0.0)), Pin("B", "fixed", "b", (0.0, 0.0)))
    theta = np.linspace(0.0, 2 * math.pi, 12, endpoint=False)
    loads = {}
    for fraction in (None, 0.5):
        mesh = Mesh("ab", "a", "b", 0.0, fraction=fraction)
        m = Machine({"fixed": Link.fixed(), "a": a, "b": b}, lumps, pins, (mesh,), (Drive("m", "a"),))
        loads[fraction] = solve(m, theta, speed=5.0)
    assert np.max(np.abs(loads[0.5].torque - loads[None].torque)) < 1e-9
    assert np.max(np.abs(loads[0.5].mesh - loads[None].mesh)) < 1e-9
    # gear b's centre on gear a (a carrier too): the mesh locks b on a, no relative instant centre
    b2 = Link("b", lambda t: (60.0 * np.cos(t0(t)), 60.0 * np.sin(t0(t)), t0(t)))
    pins2 = (Pin("A", "fixed", "a", (0.0, 0.0)), Pin("B", "a", "b", (0.0, 0.0)))
    for fraction in (None, 0.5):
        mesh = Mesh("ab", "a", "b", 0.0, fraction=fraction)
        m = Machine({"fixed": Link.fixed(), "a": a, "b": b2}, lumps, pins2, (mesh,), (Drive("m", "a"),))
        if fraction is None:
            with pytest.raises(GeometryError, match="do not turn against each other"):
                solve(m, theta, speed=5.0)
            continue
        locked = solve(m, theta, speed=5.0)
        assert locked.power_error < 1e-9
        # the mesh alone turns b about its centre: its moment, F r cos(α), is b's lump's (N mm)
        ob = 60.0 * np.stack([np.cos(theta), np.sin(theta)], axis=1)
        r = 4.0 * np.stack([-np.sin(theta), np.cos(theta)], axis=1)
        acc = -(5.0**2) * (ob + r) - np.array([0.0, -9806.65])
        needed = 0.5 * (r[:, 0] * acc[:, 1] - r[:, 1] * acc[:, 0]) * 1e-3
        assert np.allclose(locked.mesh[:, 0] * 30.0 * math.cos(math.radians(20.0)), np.abs(needed), rtol=1e-6)


def test_a_fraction_outside_the_line_of_centres_is_refused():
    with pytest.raises(SpecError, match="fraction"):
        Mesh("ab", "a", "b", 0.0, fraction=1.0)
