"""Seed 002 (Sun et al. 2023) synthesised: the design model behind ``potseedling_seed002.py``.

Table 1 gives link 2's four poses; link 3 (the planting arm) is 125 mm long with attitudes
171, 130, 154 and 167 deg at the poses. §3.3 picks the circle point (70, 33.4092) with centre
point (3.9926, 0.4983) — mechanism ③ — which :func:`chain` reproduces.

What the paper does not publish, and what we chose (see README):

* its ten intermediate points of the relative-angle curves: we place one point per gap between
  poses for each curve and let differential evolution choose them (:func:`problem`;
  ``transplanter optimise parts/_seed002.py --seed 2 --maxiter 25 --popsize 8`` gives
  ``OPTIMUM``), minimising the swing cam's largest pressure angle while keeping both gear
  stages convex;
* the centre distances of the two non-circular stages (45 mm each) and the split of the
  two-stage ratio between them (``I^λ``, λ = ``EXPONENT`` = 0.492225, the largest convexity index:
  ``chain(*OPTIMUM[:2]).distribute(CENTRE_DISTANCES, exponent=None)`` searches it, and
  ``tests/test_seed002.py`` checks the search still lands there);
* the cam follower: an oscillating roller follower (8 mm roller) whose pivot distance, arm and
  base circle are optimised with the curves.

The design studio (``transplanter design parts/potseedling_seed002.py``) draws a design with
:func:`view`: the same calls the search's cost makes, and the tray the build places — the chain and
the cam at once, the gear stages (``later``) once computed.

The leading ``_`` keeps the builder from taking this module for a part script.
"""

import math
from dataclasses import dataclass

import numpy as np
import shapely

from transplanter.core.errors import GeometryError
from transplanter.design.linkage.open_chain import Beak, OpenChain3R, RatioDistribution, seed002_poses
from transplanter.design.optimise import Problem
from transplanter.design.views import Curve, DesignView, Kept, Panel, Pose, Row, soil
from transplanter.geometry.cams import CamProfile, OscillatingRollerFollower, disc_cam
from transplanter.geometry.pitch import GearPair, PeriodicSpline
from transplanter.machine.bodies import MOTION_POSITIONS
from transplanter.machine.carriers import machine_frame
from transplanter.machine.tray import PotTray, pot_place

CIRCLE_X = 70.0  # mm, the circle point's x of mechanism ③
ARM_LENGTH = 125.0  # mm, link 3
CENTRE_DISTANCES = (45.0, 45.0)  # mm, stages 2-3 and 3-5
#: the split I^λ of OPTIMUM's two-stage ratio with the largest convexity index (both stages 0.642):
#: the part script cuts every design at it (:func:`cut_split`)
EXPONENT = 0.492225
ROLLER = 8.0  # mm, the follower's roller radius
#: intermediate points: offsets of β2 and β3 from the straight line between the poses at the
#: middle of each gap (fractions of the gap's width, rad per rad), and the follower (pivot
#: distance, arm, base radius, mm), as found by problem() with seed 2 — problem()'s variables in
#: order (the studio's "make parts" and ``transplanter optimise --write`` record a design here)
OPTIMUM_X = (-0.0344, 0.0694, 0.0219, -0.0212, 0.0176, -0.0013, -0.0532, 0.0364, 152.21, 54.45, 103.67)
#: OPTIMUM_X as (β2's offsets, β3's offsets, the follower): what the part script reads
OPTIMUM = (OPTIMUM_X[0:4], OPTIMUM_X[4:8], OPTIMUM_X[8:11])
#: the best plain design (no intermediate points, follower found alone) starts the search
START = (0.0,) * 8 + (130.7, 30.05, 99.9)

#: the search's samples of a cycle: the relative angles, the ratio split and the cam (the studio's too)
SAMPLES = 720
#: the search splits the two-stage ratio evenly (I^0.5); the part script cuts it at EXPONENT
SEARCH_EXPONENT = 0.5
#: disc_cam refuses a larger pressure angle; the search grades the pressure angle itself
PRESSURE_CEILING = math.radians(89)
#: the search's floors: the arm's speed relative to carrier 1 (β2' + β3', rad per rad of τ), the
#: smaller convexity index of the two gear stages, and how far inside its reach (|d - arm| to
#: d + arm, mm) the follower must meet the prime circle
MIN_RELATIVE_SPEED = 0.05
MIN_CONVEXITY = 0.3
REACH_SPARE = 1.0
#: an oscillating follower's pressure angle cannot stay below about half its swing; the poses
#: force 83.9 deg of swing, and the optimum reaches 45.9 deg (the paper: 43 deg, follower unpublished)
CAM_PRESSURE_LIMIT_DEG = 46.0
#: the cam as the part script cuts it: samples of its turn (CamStudy's)
CAM_SAMPLES = 3600
#: seed 002's pot tray (§2.2): pots 30 mm at the top edge, 20 at the bottom, 40 deep, the tray inclined
#: about 55 deg (requirement 6). The cell pitch is ours: the 128-cell tray of the Japanese standard for
#: fully automatic vegetable transplanters (MAFF/JA: 30 mm cells, 300 x 590 mm, 8 x 16 cells; Yanmar
#: 30-128), so at most 590/16 = 36.875 mm along its length, which we take down the slope. The picked
#: row is the tray's lowest (``lowest``): the seedling box feeds the tray down its slope and the emptied
#: tray turns under the box on its roller (seed 002 §2.1), so the cells drawn are the picked one and 4 uphill
TRAY = PotTray(pitch=590.0 / 16, top=30.0, bottom=20.0, depth=40.0, inclination_deg=55.0, lowest=True)
#: the claw enters the picked pot this deep at Table 1's pose 2 (seed 002 requirement 3), mm; the soil
#: surface lies this far above the tip's deepest point, mm; the claw's tip at the four poses may be
#: this far off Table 1 (mm, deg) — the machine's (DoubleCarrierMachineStudy) placing and judging
POT_DEPTH = 30.0
PLANTING_DEPTH = 40.0
POSE_TOLERANCE = (1.1, 0.5)


_PLAIN = Kept(1)
_CURVES = Kept(16)


def _plain() -> tuple:
    """Mechanism ③ without intermediate points: its poses, arm attitudes, circle point's y, and for
    each gap between poses its middle τ, the straight lines of β2 and β3 there and its width — the
    same for every design, so found once."""
    return _PLAIN.get((), _make_plain)


def _make_plain() -> tuple:
    poses, attitudes = seed002_poses()
    y = min(poses.circle_points_at(CIRCLE_X), key=lambda v: abs(v - 33.4092))
    plain = OpenChain3R(poses, (CIRCLE_X, y), ARM_LENGTH, attitudes)
    tau = plain.pose_tau
    mids = 0.5 * (tau + np.append(tau[1:], 2 * math.pi))
    b2 = plain.beta2(tau)
    b3 = plain.beta3(tau)
    lin2 = 0.5 * (b2 + np.roll(b2, -1))
    lin3 = 0.5 * (b3 + np.append(b3[1:], b3[0] + 2 * math.pi))
    width = np.diff(np.append(tau, 2 * math.pi))
    for a in (mids, lin2, lin3, width):
        a.setflags(write=False)
    return poses, attitudes, y, mids, lin2, lin3, width


def chain(link2_offsets=None, link3_offsets=None, beak: Beak | None = None) -> OpenChain3R:
    """Mechanism ③ with one intermediate point per gap between poses for each relative angle.

    The offsets are from the straight line between the neighbouring poses' values at the middle
    of the gap, as fractions of the gap's width in τ (so short gaps get small offsets); None puts
    no intermediate points. ``beak``: a picking beak (``_seed002_pick.py`` searches one).
    """
    poses, attitudes, y, mids, lin2, lin3, width = _plain()
    extra2 = (
        tuple(zip(mids, lin2 + width * np.asarray(link2_offsets), strict=True)) if link2_offsets is not None else ()
    )
    extra3 = (
        tuple(zip(mids, lin3 + width * np.asarray(link3_offsets), strict=True)) if link3_offsets is not None else ()
    )
    return OpenChain3R(poses, (CIRCLE_X, y), ARM_LENGTH, attitudes, extra2, extra3, beak)


def swing(ch: OpenChain3R):
    """Link 2's swing relative to link 1, from its smallest value (rad), as the cam's motion."""
    tau = 2 * math.pi * np.arange(720) / 720
    b = ch.beta2(tau)
    return PeriodicSpline(tau, b - b.min(), degree=5)


def follower(pivot, arm, base) -> OscillatingRollerFollower:
    return OscillatingRollerFollower(pivot_distance=pivot, arm_length=arm, roller_radius=ROLLER, base_radius=base)


def relative_speed(ch: OpenChain3R) -> np.ndarray:
    """β2' + β3' at the search's samples: the arm's speed relative to carrier 1 (1/I, eq 18)."""
    tau = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    return ch.beta2(tau, 1) + ch.beta3(tau, 1)


def reach(pivot, arm, base) -> tuple[float, float, float]:
    """The prime radius (base + roller) and the range the search keeps it in (mm): the follower's
    reach |d - arm| to d + arm, ``REACH_SPARE`` inside at either end."""
    return base + ROLLER, abs(pivot - arm) + REACH_SPARE, pivot + arm - REACH_SPARE


def stages(ch: OpenChain3R) -> RatioDistribution:
    """The two gear stages as the search splits the ratio (``SEARCH_EXPONENT``, ``SAMPLES``)."""
    return ch.distribute(CENTRE_DISTANCES, exponent=SEARCH_EXPONENT, samples=SAMPLES)


def cut_split(ch: OpenChain3R) -> RatioDistribution:
    """The two gear stages the part script cuts for chain ``ch``: the ratio split at ``EXPONENT``
    (the page's slow judgement and the build call this one function).

    ``EXPONENT`` is a design constant, like the centre distances: the split of OPTIMUM's largest
    convexity index. A design written from the studio is cut at it too and judged there (both
    stages' p against ``MIN_CONVEXITY``), not searched again: the index is not unimodal in λ (a
    design 0.004 off OPTIMUM in its first offset reads p = 0.557, 0.595, 0.575 and 0.599 at λ =
    0.49, 0.492225, 0.495 and 0.5, where a bounded search over [0.1, 0.9] stops at 0.506 with
    0.587), so "the best split" would be a search's accident, not a rule."""
    return ch.distribute(CENTRE_DISTANCES, exponent=EXPONENT)


def swing_cam(motion, f: OscillatingRollerFollower, n: int = SAMPLES) -> CamProfile:
    """The swing cam giving ``f`` the ``motion`` (:func:`swing`), at the search's samples unless ``n``."""
    return disc_cam(motion, f, n=n, max_pressure_angle=PRESSURE_CEILING)


def problem() -> Problem:
    """Minimise the swing cam's largest pressure angle (deg) with both gear stages convex.

    Penalties are graded so the search can climb out of infeasible corners: the arm must keep
    turning relative to carrier 1 (β2' + β3' >= 0.05), the follower must reach the cam, and the
    smaller convexity index should be >= 0.3. The swing spans at least the poses' 84 deg, and an
    oscillating follower's pressure angle cannot stay below about half its swing, so a large
    cam with a short arm is what gets under 45 deg.
    """

    def cost(x):
        ch = chain(x[0:4], x[4:8])
        rel = relative_speed(ch)
        if rel.min() < MIN_RELATIVE_SPEED:
            return 1000.0 + 1000.0 * (MIN_RELATIVE_SPEED - rel.min())
        pivot, arm, base = x[8:11]
        prime, low, high = reach(pivot, arm, base)
        if not low < prime < high:
            return 500.0 + abs(prime - 0.5 * (abs(pivot - arm) + pivot + arm))
        dist = stages(ch)
        cam = swing_cam(swing(ch), follower(pivot, arm, base))
        return math.degrees(cam.max_pressure_angle) + 50 * max(0.0, MIN_CONVEXITY - dist.p)

    names = [f"beta2_offset_gap{k}" for k in range(1, 5)] + [f"beta3_offset_gap{k}" for k in range(1, 5)]
    bounds = [(-0.1, 0.1)] * 8 + [(100.0, 250.0), (25.0, 80.0), (60.0, 120.0)]
    variables = tuple(zip(names + ["pivot_mm", "arm_mm", "base_mm"], *zip(*bounds, strict=True), strict=True))
    return Problem(
        "seed002 swing cam and gear stages",
        variables,
        cost,
        infeasible=2000.0,
        x0=START,
        view=view,
        design=OPTIMUM_X,
        optimum="OPTIMUM_X",
    )


# -- the design studio's view ---------------------------------------------------------------------


def _to_machine(frame: tuple[float, float, float], points) -> np.ndarray:
    """Points (..., 2) of the synthesis frame (Table 1's) in the machine frame ``frame``
    (:func:`~transplanter.machine.carriers.machine_frame`: p ↦ R(turn)(p - A0))."""
    cx, cy, turn = frame
    p = np.asarray(points, dtype=float) - [cx, cy]
    c, s = math.cos(turn), math.sin(turn)
    return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1]], axis=-1)


def _outlines(name: str, shape, kind: str) -> tuple[Curve, ...]:
    """A shapely (multi)polygon's outer boundaries as closed curves."""
    parts = shapely.get_parts(shape)
    return tuple(
        Curve(name, np.asarray(part.exterior.coords)[:-1], closed=True, kind=kind)
        for part in parts
        if not part.is_empty
    )


def _in_mesh(pair: GearPair, phi: np.ndarray, names: tuple[str, str]) -> tuple[Curve, Curve]:
    """An external pair's pitch curves in mesh at the start: the driver at the origin, the driven
    at the centre distance on +x, its body frame turned by π (as the report draws it)."""
    p2 = pair.driven.points(phi)
    a = pair.centre_distance
    return (
        Curve(names[0], pair.driver.points(phi), closed=True),
        Curve(names[1], np.stack([a - p2[:, 0], -p2[:, 1]], axis=1), closed=True),
    )


@dataclass(frozen=True, eq=False)
class Curves:
    """What a design's curve variables (the first eight) make, whatever its follower: the chain, the
    cam's motion, the arm's speed relative to carrier 1, the machine frame, and the panels, rows,
    pose and notes of the studio drawn from them — all but the gear stages (:func:`stage_view`),
    which take most of a design's time and are drawn after the rest."""

    chain: OpenChain3R
    motion: PeriodicSpline
    relative: np.ndarray
    frame: tuple[float, float, float]
    panels: tuple[Panel, ...]
    rows: tuple[Row, ...]
    pose: Pose
    notes: tuple[str, ...]


def curves(offsets: tuple[float, ...]) -> Curves:
    """:class:`Curves` of the curve variables ``offsets`` (8 floats), kept: moving the follower's
    pivot, arm or base circle changes none of it. GeometryError if the arm stops or reverses
    relative to carrier 1 (no gear train makes that)."""
    offsets = tuple(float(v) for v in offsets)
    return _CURVES.get(offsets, lambda: _curves(offsets))


def _turning(rel: np.ndarray) -> None:
    """GeometryError where the arm stops or reverses relative to carrier 1 at the search's samples
    (``rel``: :func:`relative_speed`) — ``OpenChain3R.distribute``'s refusal, in its words, said
    without building the gear stages."""
    if np.any(rel <= 0):
        k = int(np.argmin(rel))
        tau = 2 * math.pi * k / SAMPLES
        raise GeometryError(
            f"the arm stops or reverses relative to carrier 1 at τ = {math.degrees(tau):.2f} deg "
            f"(β2' + β3' = {rel[k]:.4g}): a gear train cannot make that motion; move the intermediate points"
        )


def _curves(offsets: tuple[float, ...]) -> Curves:
    ch = chain(offsets[0:4], offsets[4:8])
    rel = relative_speed(ch)
    _turning(rel)  # as stages(ch) would refuse it
    frame = machine_frame(ch)
    _, _, turn = frame
    turned = math.degrees(math.remainder(turn, 2 * math.pi))
    # the chain over the search's samples, in the machine frame: A0 -> A_c -> Q -> tip
    tau = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    st = ch.state(tau)
    ac, q, tip = (_to_machine(frame, p) for p in (st.circle, st.q, st.tip))
    lines = np.stack([np.zeros_like(ac), ac, q, tip], axis=1)
    pose = Pose(np.degrees(tau), lines, panel=0, label="input angle (deg)")
    # Table 1: Q and the claw's tip (Q + L3 at link 3's attitude) at the four poses
    table = np.array([[p.x, p.y] for p in ch.poses.poses])
    att = np.asarray(ch.arm_attitudes)
    wanted = table + ARM_LENGTH * np.stack([np.cos(att), np.sin(att)], axis=1)
    at_poses = ch.state(ch.pose_tau)
    tip_off = float(np.max(np.linalg.norm(at_poses.tip - wanted, axis=1)))
    # the tray as the build places it (carrier_posing.tray_place): the claw's tip at pose 2 is
    # POT_DEPTH down the picked pot's axis, the tray's normal on the side the claw points to
    mouth, axis = pot_place(
        TRAY.inclination_deg, _to_machine(frame, at_poses.tip[1]), float(at_poses.arm[1]) + turn, POT_DEPTH
    )
    walls = TRAY.walls(mouth, axis)
    # the soil PLANTING_DEPTH above the tip's deepest point (carrier_posing.soil, the same samples)
    many = 2 * math.pi * np.arange(MOTION_POSITIONS) / MOTION_POSITIONS
    level = float(_to_machine(frame, ch.state(many).tip)[:, 1].min()) + PLANTING_DEPTH
    x0, x1 = float(min(tip[:, 0].min(), q[:, 0].min())) - 60.0, float(max(tip[:, 0].max(), q[:, 0].max())) + 60.0
    frame_panel = Panel(
        f"the claw in the machine frame (Table 1's turned {turned:.1f} deg)",
        (
            *_outlines("pot tray", walls, "obstacle"),
            soil(level, x0, x1),
            *_outlines("picked pot", TRAY.pot(mouth, axis), "path"),
            Curve("claw tip", tip, closed=True),
            Curve("Q (link 2 - arm)", q, closed=True),
            Curve("A_c (link 1 - link 2)", ac, closed=True),
            Curve("Table 1 poses (Q)", _to_machine(frame, table), kind="mark"),
            Curve("claw tip at the poses", _to_machine(frame, wanted), kind="mark"),
        ),
    )
    # the relative angles over the cycle with the poses and the intermediate points (the variables)
    chart = np.linspace(0.0, 2 * math.pi, SAMPLES + 1)
    deg = np.degrees(chart)
    pt = ch.pose_tau
    ex2 = np.asarray(ch.extra_link2, dtype=float).reshape(-1, 2)
    ex3 = np.asarray(ch.extra_link3, dtype=float).reshape(-1, 2)
    angles_panel = Panel(
        "link 2 and the arm over the cycle",
        (
            Curve("β2: link 2 relative to link 1", np.stack([deg, np.degrees(ch.beta2(chart))], axis=1)),
            Curve(
                "β3 - τ: the arm relative to link 2, less τ", np.stack([deg, np.degrees(ch.beta3(chart) - chart)], 1)
            ),
            Curve(
                "poses",
                np.degrees(np.concatenate([np.stack([pt, ch.beta2(pt)], 1), np.stack([pt, ch.beta3(pt) - pt], 1)])),
                kind="mark",
            ),
            Curve(
                "intermediate points (the variables)",
                np.degrees(np.concatenate([ex2, np.stack([ex3[:, 0], ex3[:, 1] - ex3[:, 0]], axis=1)])),
                kind="mark",
            ),
        ),
        "input angle τ (deg)",
        "angle (deg)",
        equal=False,
    )
    rows = (
        Row(
            "arm relative to carrier 1: min(β2' + β3')",
            float(rel.min()),
            "",
            f">= {MIN_RELATIVE_SPEED:g}",
            float(rel.min()) - MIN_RELATIVE_SPEED,
            bool(rel.min() >= MIN_RELATIVE_SPEED),
        ),
        Row(
            "Table 1 poses: claw tip off",
            tip_off,
            "mm",
            f"<= {POSE_TOLERANCE[0]:g} mm",
            POSE_TOLERANCE[0] - tip_off,
            tip_off <= POSE_TOLERANCE[0],
        ),
    )
    inside = shapely.contains_xy(walls, tip[:, 0], tip[:, 1])
    near = float(np.min(shapely.distance(shapely.points(tip), walls)))
    notes = (
        f"machine frame: A0 at the origin, Table 1's frame turned {turned:.2f} deg so the tip's "
        f"farthest reach points down; the tray placed as the build places it (the claw's tip at pose 2, "
        f"{POT_DEPTH:g} mm down the pot's axis), the soil {PLANTING_DEPTH:g} mm above the tip's deepest point",
        (
            f"the claw's tip enters the tray's walls at {int(inside.sum())} of {SAMPLES} samples"
            if inside.any()
            else f"the claw's tip keeps {near:.2f} mm from the tray's walls"
        )
        + " (the build judges the claw's body against them: seed 002 requirement 2, a finding)",
        f"gear stages split at λ = {SEARCH_EXPONENT:g} over {SAMPLES} samples, as the search scores them; "
        f"the part script cuts them at λ = {EXPONENT:g} over 1440 (cut_split; both drawn and judged below, once "
        "computed)",
    )
    return Curves(ch, swing(ch), rel, frame, (frame_panel, angles_panel), rows, pose, notes)


def stage_view(ch: OpenChain3R) -> tuple[tuple[Panel, ...], tuple[Row, ...]]:
    """The gear stages of chain ``ch`` as the search splits them (:func:`stages`): the ratio split
    over the cycle and both stages' pitch curves in mesh (panels), and the smaller convexity index
    (a row). GeometryError if the arm stops or reverses relative to carrier 1."""
    dist = stages(ch)
    chart = np.linspace(0.0, 2 * math.pi, SAMPLES + 1)
    deg = np.degrees(chart)
    p23, p35 = dist.stage23, dist.stage35
    ratios_panel = Panel(
        f"ratio split I^{SEARCH_EXPONENT:g} (the search's): speeds relative to carrier 1",
        (
            Curve("β2' + β3' = 1/I (arm)", np.stack([deg, ch.beta2(chart, 1) + ch.beta3(chart, 1)], axis=1)),
            Curve("stage 2-3: ω3/ω2", np.stack([deg, p23.ratio(chart)], axis=1)),
            Curve("stage 3-5: ω5/ω3", np.stack([deg, p35.ratio(p23.driven_rotation(chart))], axis=1)),
            Curve(f"floor {MIN_RELATIVE_SPEED:g}", np.array([[0.0, MIN_RELATIVE_SPEED], [360.0, MIN_RELATIVE_SPEED]])),
        ),
        "input angle τ (deg)",
        "ratio",
        equal=False,
    )
    phi = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    pitch_panels = tuple(
        Panel(f"{what} pitch curves, a = {pair.centre_distance:g} mm, p = {p:.3f}", _in_mesh(pair, phi, names))
        for what, pair, p, names in (
            ("stage 2-3", p23, dist.convexity[0], ("sun 2", "gear 3")),
            ("stage 3-5", p35, dist.convexity[1], ("gear 4", "gear 5")),
        )
    )
    row = Row(
        "gear stages: smaller convexity index p",
        dist.p,
        "",
        f">= {MIN_CONVEXITY:g}",
        dist.p - MIN_CONVEXITY,
        dist.p >= MIN_CONVEXITY,
    )
    return (ratios_panel, *pitch_panels), (row,)


def view(x) -> DesignView:
    """What ``transplanter design`` draws of design ``x``: the claw's path in the machine frame
    with Table 1's poses, the tray and the soil, and the chain posed at every sample; the swing cam
    with its follower; the relative angles over the cycle; the search's objectives but the gear
    stages' (the calls its cost makes). Then (``later``, a :class:`DesignView` of panels and rows)
    the gear stages as the search splits them — the ratio split over the cycle, both stages' pitch
    curves, their smaller convexity index — and the stages and the cam as the part script cuts
    them. A design the model rejects raises its TransplanterError (the follower cannot reach the
    cam, the arm reverses, the cam undercuts)."""
    x = tuple(float(v) for v in x)
    drawn = curves(x[:8])
    pivot, arm, base = x[8:11]
    f = follower(pivot, arm, base)  # GeometryError if the arm cannot reach the prime circle at all
    cam = swing_cam(drawn.motion, f)
    prime, low, high = reach(pivot, arm, base)
    k = int(np.argmax(cam.pressure_angle))
    worst = math.degrees(cam.max_pressure_angle)
    t = cam.theta[k]
    lever = np.array([[pivot * math.cos(t), -pivot * math.sin(t)], cam.pitch[k]])  # the cam's frame: R(-θ)
    ring = np.linspace(0.0, 2 * math.pi, 181)[:-1]
    circle = np.stack([np.cos(ring), np.sin(ring)], axis=1)
    cam_panel = Panel(
        f"swing cam, the follower at its worst: θ = {math.degrees(t):.1f} deg",
        (
            Curve("cam profile", cam.profile, closed=True),
            Curve("pitch curve (roller centre)", cam.pitch, closed=True),
            Curve("base circle", base * circle, closed=True),
            Curve("follower lever", lever),
            Curve("roller", cam.pitch[k] + ROLLER * circle, closed=True),
            Curve("follower pivot's circle", pivot * circle, closed=True),
            Curve("cam axis, follower pivot", np.array([[0.0, 0.0], lever[0]]), kind="mark"),
        ),
    )
    margin = min(prime - low, high - prime)
    rows = (
        Row(
            "swing cam: largest pressure angle",
            worst,
            "deg",
            f"<= {CAM_PRESSURE_LIMIT_DEG:g} deg",
            CAM_PRESSURE_LIMIT_DEG - worst,
            worst <= CAM_PRESSURE_LIMIT_DEG,
        ),
        Row(
            "swing cam: smallest convex radius of the profile",
            cam.min_convex_radius,
            "mm",
            "> 0 mm (no undercut)",
            cam.min_convex_radius,
            cam.min_convex_radius > 0,
        ),
        Row(
            "follower reaches the cam: prime radius (base + roller)",
            prime,
            "mm",
            f"{low:.2f} < r < {high:.2f} mm",
            margin,
            margin > 0,
        ),
        *drawn.rows,
    )
    ch, motion = drawn.chain, drawn.motion

    def later() -> DesignView:
        panels, searched = stage_view(ch)
        cut = cut_split(ch)
        made = math.degrees(swing_cam(motion, f, n=CAM_SAMPLES).max_pressure_angle)
        out = tuple(
            Row(
                f"{what} as cut (λ = {cut.exponent:.6g}): convexity index p",
                p,
                "",
                f">= {MIN_CONVEXITY:g}",
                p - MIN_CONVEXITY,
                p >= MIN_CONVEXITY,
            )
            for what, p in zip(("stage 2-3", "stage 3-5"), cut.convexity, strict=True)
        )
        cam_row = Row(
            f"swing cam as cut ({CAM_SAMPLES} samples): largest pressure angle",
            made,
            "deg",
            f"<= {CAM_PRESSURE_LIMIT_DEG:g} deg",
            CAM_PRESSURE_LIMIT_DEG - made,
            made <= CAM_PRESSURE_LIMIT_DEG,
        )
        return DesignView(panels, (*searched, *out, cam_row))

    panels = (drawn.panels[0], cam_panel, *drawn.panels[1:])
    return DesignView(
        panels,
        rows,
        drawn.pose,
        drawn.notes,
        later=later,
        later_title=(
            f"the gear stages (the search's split λ = {SEARCH_EXPONENT:g}), then the stages and the cam "
            "as the part script cuts them (potseedling_seed002.py)"
        ),
    )
