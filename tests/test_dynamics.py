"""The machine under load (issue 44): the generic inverse dynamics of :mod:`transplanter.machine.dynamics`
against the four-bar's own Newton-Euler (seed 003's equations, which the project holds to seed 003's
Table 4), Newton-Euler against virtual power on a non-circular planetary train, the mesh force's
line through the pitch point, the supports' shares, the mass of a slab, refusals."""

import math

import numpy as np
import pytest

from transplanter.core.errors import SpecError
from transplanter.design.linkage import dynamics as fourbar_dynamics
from transplanter.design.linkage.fourbar import Link as FourBarLink
from transplanter.design.planetary import ArmGeometry, DifferentialTrain
from transplanter.families import load_family
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.machine.bodies import Link, PlanetaryMachine
from transplanter.machine.dynamics import Drive, Machine, Mesh, Pin, PointLoad, angular_speed, equivalent_load, solve
from transplanter.machine.mass import Lump, slab_lump, to_link_frame


@pytest.fixture(scope="module")
def type_i(parts_dir):
    return {p.name: p for p in load_family(parts_dir / "fourbar_seed003.py").parts}["type_I"]


def _fourbar_machine(study) -> Machine:
    fb, masses = study.linkage, study.masses

    def pose(which):
        def f(t):
            motion = fb.solve(fb.ground_angle + np.asarray(t, dtype=float))
            j = motion.joints()
            origin = {FourBarLink.CRANK: j["O2"], FourBarLink.COUPLER: j["B"], FourBarLink.ROCKER: j["O4"]}[which]
            return origin[:, 0], origin[:, 1], motion.theta[which]

        return f

    names = {FourBarLink.CRANK: "crank", FourBarLink.COUPLER: "coupler", FourBarLink.ROCKER: "rocker"}
    links = {name: Link(name, pose(which)) for which, name in names.items()}
    lumps = {
        name: (Lump(masses.of(which).mass, (*masses.of(which).com, 0.0), masses.of(which).inertia),)
        for which, name in names.items()
    }
    pins = (
        Pin("O2", "fixed", "crank", (0.0, 0.0)),
        Pin("B", "crank", "coupler", (0.0, 0.0)),
        Pin("C", "coupler", "rocker", (0.0, 0.0), point=(fb.rocker, 0.0)),
        Pin("O4", "fixed", "rocker", (0.0, 0.0)),
    )
    return Machine(links, lumps, pins, drives=(Drive("crank motor", "crank"),))


def test_the_generic_solver_is_the_fourbars_newton_euler(type_i):
    """Seed 003's type I finger at its speed: the generic solver (poses differentiated by five-point
    stencils) gives the four-bar module's crank torque and pin forces (closed-form rates, seed 003
    eqs 19-24) to 1e-6 of their largest; its own virtual power agrees to 1e-8."""
    fb, speed = type_i.linkage, type_i.crank_speed
    theta = 2 * math.pi * np.arange(72) / 72
    ours = solve(_fourbar_machine(type_i), theta, speed)
    theirs = fourbar_dynamics.joint_forces(fb.solve(fb.ground_angle + theta, speed), type_i.masses)
    scale = float(np.max(np.abs(theirs.torque)))
    assert float(np.max(np.abs(ours.torque[:, 0] - theirs.torque))) < 1e-6 * scale
    for j, f in enumerate(
        (theirs.ground_on_crank, theirs.crank_on_coupler, theirs.coupler_on_rocker, theirs.ground_on_rocker)
    ):
        assert float(np.max(np.abs(ours.pin[:, j] - f))) < 1e-6 * float(np.max(np.abs(f)))
    assert ours.power_error < 1e-8
    # the shaking force is -Σ m a, what the frame's pins carry less the weight
    weight = np.array([0.0, -type_i.masses.total_mass * fourbar_dynamics.STANDARD_GRAVITY])
    assert np.allclose(ours.frame_force - weight, ours.shaking_force, atol=1e-6 * scale)
    assert np.allclose(
        ours.shaking_force,
        fourbar_dynamics.shaking_force(fb.solve(fb.ground_angle + theta, speed), type_i.masses),
        atol=1e-5,
    )


def _train() -> DifferentialTrain:
    pair = GearPair.from_driver(PitchCurve.ellipse(80.0, 0.1, lobes=4), "internal", driven_lobes=1)
    return DifferentialTrain(pair, ArmGeometry(tip=150.0, knee=80.0, mount=-0.7), carrier_start=0.7)


def _planetary(train: DifferentialTrain, tip_force: float = 40.0) -> Machine:
    links = PlanetaryMachine(train).links
    lumps = {
        "ring": (Lump(3.0, (0.5, -0.2, -20.0), 2.0e4),),
        "carrier": (Lump(4.0, (0.0, 0.0, 15.0), 3.0e4),),
    }
    pins = [Pin("ring", "fixed", "ring", (-60.0, -30.0)), Pin("carrier", "ring", "carrier", (-50.0, 20.0))]
    meshes, loads = [], []
    tip = tuple(float(v) for v in np.array([math.cos(train.arm.mount), math.sin(train.arm.mount)]) * train.arm.tip)
    for k in range(1, train.planets + 1):
        lumps[f"planet.{k}"] = (Lump(0.3, (2.0, 1.0, 5.0), 300.0), Lump(0.2, (60.0, -30.0, 30.0), 500.0))
        pins.append(Pin(f"planet {k}", "carrier", f"planet.{k}", (-5.0, 25.0)))
        meshes.append(Mesh(f"mesh {k}", "ring", f"planet.{k}", 6.0, ring="a"))
        # a constant downward pull at the tip: the loads' power enters virtual power
        loads.append(
            PointLoad(f"tip {k}", f"planet.{k}", tip, 35.0, lambda t, p, v: np.tile([0.0, -tip_force], (len(t), 1)))
        )
    drives = (Drive("ring motor", "ring"), Drive("carrier motor", "carrier"))
    return Machine(links, lumps, tuple(pins), tuple(meshes), drives, tuple(loads))


def test_newton_euler_and_virtual_power_agree_on_a_non_circular_train():
    """The issue's done-when: the drives' power by Newton-Euler equals the energy rate (kinetic +
    potential) less the loads' power, to 1e-6 of the largest — here to 1e-7 (measured 1.2e-8); each
    mesh force pushes (>= 0) along its tooth line through the pitch point (the gears' relative
    instant centre), which lies on the carrier line at the ring's pitch radius there."""
    train = _train()
    m = _planetary(train)
    theta = 2 * math.pi * np.arange(180) / 180
    loads = solve(m, theta, speed=2 * math.pi)
    assert loads.power_error < 1e-7
    assert np.all(loads.mesh >= 0.0)
    ring = m.links["ring"]
    for k in range(train.planets):
        p = loads.pitch_point[:, k]
        centre = np.stack(m.links[f"planet.{k + 1}"].pose(theta)[:2], axis=1)
        # on the line from O through the planet centre, at the ring's pitch radius there
        cross = p[:, 0] * centre[:, 1] - p[:, 1] * centre[:, 0]
        assert np.max(np.abs(cross)) < 1e-6 * 80.0 * train.pair.centre_distance
        a_ring = np.asarray(ring.pose(theta)[2]) * np.ones_like(theta)
        polar = np.arctan2(p[:, 1], p[:, 0]) - a_ring
        r_ring = train.pair.driver.r(polar)
        assert np.max(np.abs(np.linalg.norm(p, axis=1) - r_ring)) < 1e-6 * 80.0
    assert np.allclose(np.linalg.norm(loads.mesh_line, axis=2), 1.0)


def test_a_tip_load_costs_its_power_and_nothing_else():
    """Twice the tip load: the drives' extra mean power is the loads' extra mean power (here 0 on
    the cycle — a constant force on a closed path does no net work), to 1e-9 W."""
    train = _train()
    theta = 2 * math.pi * np.arange(120) / 120
    a = solve(_planetary(train, 40.0), theta, 2 * math.pi)
    b = solve(_planetary(train, 80.0), theta, 2 * math.pi)
    assert abs(float(np.mean(b.power - a.power))) < 1e-9 * float(np.max(np.abs(b.power)))
    assert float(np.max(np.abs(b.torque - a.torque))) > 1.0  # but the torques do differ


def test_the_supports_share_a_pin_by_the_lever_rule():
    """A rotor of 2 kg whose centre is 30 mm from the rear support of two 100 mm apart: the rear
    takes 70 % of its weight and of its unbalance force, the front 30 %."""
    rotor = Link("rotor", lambda t: (np.zeros_like(t), np.zeros_like(t), np.asarray(t, dtype=float)))
    m = Machine(
        {"rotor": rotor},
        {"rotor": (Lump(2.0, (10.0, 0.0, 30.0), 50.0),)},
        pins=(Pin("axle", "fixed", "rotor", (0.0, 100.0)),),
        drives=(Drive("motor", "rotor"),),
    )
    theta = np.linspace(0.0, 2 * math.pi, 16, endpoint=False)
    loads = solve(m, theta, speed=30.0)
    total = loads.pin[:, 0]
    assert np.allclose(loads.support[:, 0, 0], 0.7 * total, atol=1e-9)
    assert np.allclose(loads.support[:, 0, 1], 0.3 * total, atol=1e-9)
    # the unbalance: m r ω² = 2 kg × 0.01 m × 900 = 18 N about the weight
    assert float(np.max(np.linalg.norm(total - [0.0, 2.0 * 9.80665], axis=1))) == pytest.approx(18.0, rel=1e-8)
    assert np.allclose(angular_speed(rotor, theta, 30.0), 30.0)


def test_an_indeterminate_machine_is_refused_naming_the_count():
    bar = Link("bar", lambda t: (np.zeros_like(t), np.zeros_like(t), np.asarray(t, dtype=float)))
    m = Machine({"bar": bar}, {"bar": (Lump(1.0, (50.0, 0.0, 0.0)),)}, pins=(Pin("O", "fixed", "bar", (0.0, 1.0)),))
    with pytest.raises(SpecError, match=r"2 unknown forces and torques .* for 3 equations"):
        solve(m, np.zeros(3), 1.0)
    with pytest.raises(SpecError, match=r"link 'nowhere' is not a link"):
        solve(
            Machine({"bar": bar}, {}, pins=(Pin("O", "fixed", "nowhere", (0.0, 1.0)),), drives=(Drive("d", "bar"),)),
            np.zeros(2),
            1.0,
        )


def test_a_slab_lump_is_its_annulus():
    """An annulus R 50, r 20, 10 mm thick in steel: m = ρ t π (R² - r²), I = m (R² + r²) / 2,
    its centre moved and turned by its placement, then carried into a link's frame."""

    def circle(r, n=4000):
        a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)

    rho = 7.85e-6
    at = np.eye(4)
    at[:3, 3] = [100.0, -40.0, 5.0]
    lump = slab_lump([(circle(50.0), False), (circle(20.0)[::-1], True)], 2.0, 10.0, rho, at)
    mass = rho * 10.0 * math.pi * (50.0**2 - 20.0**2)
    assert lump.mass == pytest.approx(mass, rel=1e-5)
    assert lump.izz == pytest.approx(mass * (50.0**2 + 20.0**2) / 2, rel=1e-5)
    assert lump.com == pytest.approx((100.0, -40.0, 12.0), abs=1e-9)
    local = to_link_frame(lump, (100.0, 0.0, math.pi / 2))
    assert local.com == pytest.approx((-40.0, 0.0, 12.0), abs=1e-9)


def test_the_equivalent_load_is_the_cube_mean_by_revolutions():
    assert equivalent_load(np.full(5, 300.0), np.ones(5)) == pytest.approx(300.0)
    # half the revolutions at 100 N, half at 200 N: (0.5 (100³ + 200³))^(1/3)
    assert equivalent_load(np.array([100.0, 200.0]), np.array([1.0, 1.0])) == pytest.approx(4.5e6 ** (1 / 3))
    assert equivalent_load(np.array([100.0, 200.0]), np.array([0.0, 0.0])) == 200.0
