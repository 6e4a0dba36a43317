"""Seed 002's picking beak, searched against the pot tray (requirement 2; issue 42).

Seed 002 §2.1 asks for "a trajectory with a sharp shape for picking seedlings": the claw goes
into a pot of the tray and comes back out along its own line. ``_seed002.OPTIMUM`` was searched for
the swing cam's pressure angle alone and has no beak: its tip runs on through Table 1's pose 2, and
the arm, its hub and the claw cross the tray's walls (``results.machine.tray``). This problem asks
whether mechanism ③ — Table 1's poses and attitudes, the circle point of §3.3 — can pick at all,
with a cam and two gear stages that make it:
the curve variables of ``_seed002.problem`` and the follower, plus a :class:`Beak` placed between
pose 1 (start of picking) and pose 2 (end of picking), where the tip stands still and leaves along
the claw (exact: ``OpenChain3R``'s beak knots).

The tray is placed as the machine places it, from the beak: the picked pot's axis along the claw
there, the tip ``PICK_DEPTH`` down it (requirement 3 asks 30 mm), the cells uphill of it. Its
inclination is what the claw's attitude makes it; requirement 6 (the claw turns 50–60° between
picking and pushing, and the tray lies about 55°, so the seedling stands upright at the push) is
kept both ways: the beak's claw stands ``turn_deg`` (50–60) from its attitude at pose 3 (the start
of pushing), and the tray's inclination in the machine frame must fall within 50–60° too.

The measure (:func:`pick_margin`) is the machine's own: the arm and claw outlines the build cuts
(``carrier_parts.arm`` and ``carrier_parts.claw`` at the machine's sizes), each station along the
arm a disc as wide as the outline there (so it covers it), its centre's signed distance to the
tray's walls — and to the picked pot's soil for the arm (the claw's is its work) — less the disc
and ``CLEARANCE``, at the search's 720 samples of the turn. A negative margin is how far a body
crosses the tray. 720 positions are a screen, not a bound: where the tip runs fast they can step
over a narrow dip (``PICK`` reads 0.56 mm there and −0.81 mm 100 times finer). The search's cost
sums every shortfall — the tray, requirement 6, the arm turning relative to carrier 1, the
follower's reach, the cam's pressure angle past
``CAM_PRESSURE_LIMIT_DEG``, the stages' convexity under ``MIN_CONVEXITY`` — and a design short of
none costs its cam's largest pressure angle, as ``_seed002.problem`` does.

Run: ``transplanter optimise parts/_seed002_pick.py --seed 5 --maxiter 400 --popsize 10 --workers 2``
(``--set side=-1`` turns the beak's claw the other way from pose 3's attitude). ``PICK`` is the
best design found so far, by the search it names; between the search's positions its margin is
negative — see docs/mechanisms/machines.md, "Seed 002's pot tray".

The leading ``_`` keeps the builder from taking this module for a part script.
"""

import dataclasses
import math

import numpy as np
import shapely
from _seed002 import (
    ARM_LENGTH,
    CAM_PRESSURE_LIMIT_DEG,
    MIN_CONVEXITY,
    MIN_RELATIVE_SPEED,
    SAMPLES,
    TRAY,
    _to_machine,
    chain,
    follower,
    reach,
    relative_speed,
    stages,
    swing,
    swing_cam,
)

from transplanter.core.errors import GeometryError
from transplanter.design.linkage.open_chain import Beak, OpenChain3R, seed002_poses
from transplanter.design.optimise import Problem
from transplanter.families.machines.carrier_machine import DoubleCarrierMachineStudy
from transplanter.families.machines.carrier_making import ARM_BOSS_MM, ARM_HUB_MM
from transplanter.geometry.contact import segment_distance
from transplanter.machine import carrier_parts
from transplanter.machine.carriers import machine_frame

#: the claw's tip this deep in the picked pot at the beak (requirement 3: at least 30), mm
PICK_DEPTH = 32.0
#: between the arm or claw and the tray, as between every two bodies of the machine
#: (potseedling_seed002.CLEARANCE), mm
CLEARANCE = 3.0
#: requirement 6: the claw's turn between picking and pushing, and the tray's inclination, deg
TURN_RANGE = (50.0, 60.0)
#: the best design found for the tray (variables in problem()'s order, side 1): the search when it
#: graded the tray first (``--seed 5``, then ``--seed 6`` from it); 0.56 mm at the search's 720
#: positions, −0.81 mm between them, and no cam and gear stages make it (docs/mechanisms/machines.md)
PICK = (
    0.1753407467284228,
    -0.12437340087394017,
    0.10307257618284034,
    0.05118091046153919,
    0.09575751580587939,
    -0.09054253027299103,
    0.006407434469927953,
    -0.08231697146250855,
    208.8848986631101,
    31.875730507807685,
    84.58076284781656,
    80.02767725456782,
    -9.497160140342231,
    54.636609521884964,
    219.8171405209711,
    0.04670937884040208,
    -0.2298529919067808,
    -0.31265990750307643,
    0.19493001478692237,
    0.3706238264324575,
)


def _made(field: str) -> float:
    return float({f.name: f.default for f in dataclasses.fields(DoubleCarrierMachineStudy)}[field])


#: the arm's and the claw's outlines as the machine cuts them, in the arm's frame (Q at the origin,
#: the tip on +x, mm)
ARM_OUTLINE = carrier_parts.arm(ARM_LENGTH, ARM_HUB_MM, ARM_BOSS_MM, _made("claw_at"))
CLAW_OUTLINE = carrier_parts.claw(ARM_LENGTH, _made("claw_at") - ARM_BOSS_MM, _made("claw_width"), _made("claw_tab"))
#: stations along the arm (mm from Q), 2 mm apart
STATIONS = np.linspace(0.0, 126.0, 64)


def outline_radii(outline, stations: np.ndarray) -> np.ndarray:
    """The farthest the ``outline`` reaches from the arm's line (mm) within a station's reach either
    side of each of ``stations`` (mm from Q; nan where it has none): a disc that wide round the
    station covers the outline there."""
    half = (stations[1] - stations[0]) / 2
    out = []
    for s in stations:
        cut = shapely.intersection(outline, shapely.box(s - half, -200.0, s + half, 200.0))
        if cut.is_empty:
            out.append(np.nan)
            continue
        c = shapely.get_coordinates(cut)
        out.append(float(np.max(np.hypot(c[:, 0] - s, c[:, 1]))))
    return np.array(out)


ARM_RADII = outline_radii(ARM_OUTLINE, STATIONS)
CLAW_RADII = outline_radii(CLAW_OUTLINE, STATIONS)


def pick_chain(x) -> OpenChain3R:
    """The chain of design ``x`` (problem()'s order), its beak's claw ``turn_deg`` counter-clockwise
    from pose 3's attitude (problem()'s default ``side``)."""
    return _chain(x, 1.0)


def _chain(x, side: float) -> OpenChain3R:
    att = seed002_poses()[1]
    tau, beta2, turn, sharpness, spread = (float(v) for v in x[11:16])
    beak = Beak(
        math.radians(tau),
        math.radians(beta2),
        att[2] + side * math.radians(turn),
        sharpness,
        spread,
        tuple(float(v) for v in x[16:20]),
    )
    return chain(x[0:4], x[4:8], beak)


def _to_boundary(poly, points: np.ndarray) -> np.ndarray:
    """Each of ``points``' (n, 2) distance (mm) to the boundary of ``poly``, segment by segment (a
    few: faster than making n shapely points)."""
    best = np.full(len(points), np.inf)
    for ring in shapely.get_parts(shapely.boundary(poly)):
        c = shapely.get_coordinates(ring)
        for a, b in zip(c[:-1], c[1:], strict=True):
            ends = (np.broadcast_to(a, points.shape), np.broadcast_to(b, points.shape))
            best = np.minimum(best, segment_distance(points, *ends))
    return best


def _tray(ch: OpenChain3R, frame) -> tuple[shapely.Polygon, shapely.Polygon]:
    """The tray's walls and the picked pot, placed by chain ``ch``'s beak (module docstring)."""
    if ch.beak is None:
        raise GeometryError("a pick needs a chain with a beak")
    beak_tip = _to_machine(frame, ch.state([ch.beak.tau]).tip)[0]
    axis = ch.beak.attitude + frame[2]
    mouth = beak_tip - PICK_DEPTH * np.array([math.cos(axis), math.sin(axis)])
    return TRAY.walls(mouth, axis), TRAY.pot(mouth, axis)


def pick_margins_at(ch: OpenChain3R, tau, frame=None) -> np.ndarray:
    """Requirement 2's margin (mm) at each carrier rotation ``tau`` (rad): the least over the
    stations of the arm's disc against the walls and the pot and the claw's against the walls,
    less ``CLEARANCE``; negative where a body crosses the tray. ``frame``: ``machine_frame(ch)``
    if known."""
    frame = machine_frame(ch) if frame is None else frame
    walls, pot = _tray(ch, frame)
    both = shapely.union(walls, pot)
    st = ch.state(np.asarray(tau, dtype=float))
    tip, q = _to_machine(frame, st.tip), _to_machine(frame, st.q)
    along = (tip - q) / ch.arm_length
    pts = q[:, None, :] + STATIONS[None, :, None] * along[:, None, :]
    flat = pts.reshape(-1, 2)

    def signed(poly):
        d = _to_boundary(poly, flat)
        return np.where(shapely.contains_xy(poly, flat[:, 0], flat[:, 1]), -d, d).reshape(pts.shape[:-1])

    arm = np.where(np.isnan(ARM_RADII), np.inf, signed(both) - ARM_RADII)
    claw = np.where(np.isnan(CLAW_RADII), np.inf, signed(walls) - CLAW_RADII)
    return np.minimum(arm, claw).min(axis=1) - CLEARANCE


def pick_margin(ch: OpenChain3R) -> tuple[float, float, float]:
    """(margin mm, inclination deg, τ deg where least) of chain ``ch``'s beak against the tray
    placed by it, at the search's samples (:func:`pick_margins_at`)."""
    tau = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    frame = machine_frame(ch)
    m = pick_margins_at(ch, tau, frame)
    k = int(np.argmin(m))
    axis = ch.beak.attitude + frame[2]
    inclination = abs(math.degrees(math.remainder(axis + math.pi / 2, 2 * math.pi)))
    return float(m[k]), inclination, math.degrees(tau[k])


def problem(side: float = 1.0) -> Problem:
    """A beak between poses 1 and 2 that picks from the tray (module docstring); ``side`` 1 turns
    its claw counter-clockwise from pose 3's attitude (down and away from the machine's centre on
    the side of pose 2), -1 clockwise."""
    if side not in (-1.0, 1.0):
        raise GeometryError(f"side = {side!r}: give -1 or 1")
    lo, hi = TURN_RANGE

    def judged(x) -> tuple[float, dict[str, tuple[float, float, str]]]:
        """The cam's largest pressure angle (deg) and each requirement's (value, margin, unit)."""
        ch = _chain(x, side)
        rel = relative_speed(ch)
        margin, inclination, at = pick_margin(ch)
        pivot, arm, base = x[8:11]
        prime, low, high = reach(pivot, arm, base)
        try:
            pressure = math.degrees(swing_cam(swing(ch), follower(pivot, arm, base)).max_pressure_angle)
        except GeometryError:  # no cam gives that swing to that follower under PRESSURE_CEILING
            pressure = 90.0
        try:
            p = stages(ch).p if rel.min() > 0 else -math.inf
        except GeometryError:
            p = -math.inf
        return pressure, {
            f"requirement 2 (arm and claw clear of the tray, least at {at:.1f} deg)": (margin, margin, "mm"),
            "requirement 6 (tray inclination)": (inclination, (hi - lo) / 2 - abs(inclination - (hi + lo) / 2), "deg"),
            "arm turning relative to carrier 1": (rel.min(), rel.min() - MIN_RELATIVE_SPEED, "rad/rad"),
            "follower's reach to the prime circle": (prime, min(prime - low, high - prime), "mm"),
            "swing cam's largest pressure angle": (pressure, CAM_PRESSURE_LIMIT_DEG - pressure, "deg"),
            "gear stages' convexity index": (p, p - MIN_CONVEXITY, ""),
        }

    weights = (10.0, 10.0, 100.0, 0.1, 1.0, 50.0)

    def cost(x):
        # every shortfall graded and summed, so the search weighs the tray against what a cam and
        # two gear stages can make; a design short of none costs its cam's pressure angle (deg)
        pressure, rows = judged(x)
        short = sum(min(100.0, w * max(0.0, -m)) for w, (_, m, _) in zip(weights, rows.values(), strict=True))
        return pressure + (100.0 + short if short > 0 else 0.0)

    def describe(x):
        return {k: f"{v:.4g} {unit} (margin {m:.4g})".replace("  ", " ") for k, (v, m, unit) in judged(x)[1].items()}

    names = [f"beta2_offset_gap{k}" for k in range(1, 5)] + [f"beta3_offset_gap{k}" for k in range(1, 5)]
    bounds = [(-0.2, 0.2)] * 8 + [(100.0, 250.0), (25.0, 80.0), (60.0, 120.0)]
    names += ["pivot_mm", "arm_mm", "base_mm"]
    names += ["beak_tau_deg", "beak_beta2_deg", "turn_deg", "sharpness_mm_per_rad2", "spread_rad"]
    bounds += [(3.0, 181.0), (-10.0, 115.0), TURN_RANGE, (40.0, 800.0), (0.04, 0.3)]
    names += ["shape_beta2_before", "shape_beta2_after", "shape_beta3_before", "shape_beta3_after"]
    bounds += [(-0.4, 0.4)] * 4
    return Problem(
        "seed002 picking beak against the pot tray",
        tuple(zip(names, *zip(*bounds, strict=True), strict=True)),
        cost,
        infeasible=5000.0,
        x0=PICK,
        describe=describe,
        optimum="PICK",
    )
