"""The studio's view of an incomplete gear pair (a law with dwells, :mod:`~transplanter.geometry.pitch.intermittent`):
the two pitch curves at their centres, the ratio over the driver angle, the pitch curves'
pressure deviation, both gears posed at every sample of the driver's turn, and the cheap checks
of the law at its size (:func:`pair_checks`: what the pair family asks of it before it cuts).

Everything is the library's: the sized :class:`~transplanter.geometry.pitch.intermittent.IncompletePair`
(``IncompletePairStudy.pair``), its radii, ratio, pressure deviation and curvature. The meshing
frame is the library's (:func:`~transplanter.geometry.pitch.driven_axis`,
:func:`~transplanter.geometry.pitch.driven_turn`): the driver's axis at the origin, turning
clockwise by the driver angle, the driven's on the x axis. Over a dwell the driver's pitch curve
is drawn at the sector's radius at the dwell's ends (``IncompletePair.driver``: the locking arc
that the cut puts there is smaller, :func:`transplanter.geometry.incomplete.cut_incomplete`).
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import check_int
from transplanter.design.views import Curve, DesignView, Panel, Pose, Row
from transplanter.geometry.pitch import driven_axis, driven_turn
from transplanter.geometry.pitch.intermittent import CLOSURE_ROUND_OFF, MIN_RATIO, IncompletePair

__all__ = ["SAMPLES", "incomplete_pair_view", "pair_checks", "limit_row"]

#: samples of each motion where the checks take their extremes (as the law's own checks and the
#: proof's backlash band do: ``IntermittentLaw``, ``IncompleteProof.band``)
SAMPLES = 2001


def limit_row(name: str, value: float, unit: str, limit: float, at_most: bool, why: str = "") -> Row:
    """A :class:`~transplanter.design.views.Row` of ``value`` against ``limit`` (at most or at least)."""
    margin = limit - value if at_most else value - limit
    said = f"{'<=' if at_most else '>='} {limit:.4g} {unit}".strip() + (f" ({why})" if why else "")
    return Row(name, float(value), unit, said, float(margin), bool(margin >= 0.0))


def _motion_angles(pair: IncompletePair, n: int = SAMPLES) -> list[tuple[object, np.ndarray]]:
    return [(m, np.linspace(math.radians(m.start), math.radians(m.end), n)) for m in pair.law.motions]


def pair_checks(pair: IncompletePair, cutter_radius: float, max_pressure_deviation_deg: float) -> tuple[Row, ...]:
    """The law at its size as the pair family checks it before cutting, each against its limit:
    the closure (the driven turns 1/n2 of a turn per driver turn, to ``CLOSURE_ROUND_OFF``), the
    smallest ratio of every motion (``MIN_RATIO``), the pitch curves' largest pressure deviation
    (against ``max_pressure_deviation_deg``) and each gear's least curvature over its sectors
    (an external gear's concave parts must be rounder than the shaper's pitch radius
    ``cutter_radius``, mm, as ``ShaperCutter.check_fits`` refuses; a ring's convex parts the same)."""
    law = pair.law
    n2 = law.turn_fraction
    closure = abs(law.total_rise - 2 * math.pi / n2)
    rows = [
        limit_row(
            f"closure error (the driven turns 1/{n2} per driver turn)",
            closure,
            "rad",
            CLOSURE_ROUND_OFF * 2 * math.pi / n2,
            True,
            "round-off",
        )
    ]
    sampled = _motion_angles(pair)
    least = min(float(m.ratio(phi).min()) for m, phi in sampled)
    rows.append(limit_row("smallest ratio w2/w1", least, "", MIN_RATIO, False, "a tooth carries it"))
    nu = max(float(np.max(np.abs(pair.pressure_deviation(phi, m)))) for m, phi in sampled)
    rows.append(
        limit_row("pitch-curve pressure deviation", math.degrees(nu), "deg", max_pressure_deviation_deg, True, "stated")
    )
    ring = pair.ring
    for role in ("driver", "driven"):
        k = np.concatenate([pair.curvature(phi, role, m) for m, phi in sampled])
        if ring == role:  # the cutter rolls inside a ring: its convex parts must be rounder than the cutter
            rows.append(
                limit_row(
                    f"{role} sectors: largest curvature", float(k.max()), "1/mm", 1 / cutter_radius, True, "cutter"
                )
            )
        else:
            rows.append(
                limit_row(
                    f"{role} sectors: least curvature (convex > 0)",
                    float(k.min()),
                    "1/mm",
                    -1 / cutter_radius,
                    False,
                    f"concave radius > the cutter's {cutter_radius:g} mm",
                )
            )
    return tuple(rows)


def incomplete_pair_view(
    pair: IncompletePair,
    rows: tuple[Row, ...],
    max_pressure_deviation_deg: float | None = None,
    n: int = 360,
    notes: tuple[str, ...] = (),
) -> DesignView:
    """The :class:`~transplanter.design.views.DesignView` of the sized ``pair`` with the
    objectives ``rows``: the pitch curves at their centres (posed at driver angle 0), the ratio
    ω2/ω1 over the driver angle, the pressure deviation over the motions (with its limit when
    given, deg), and ``n`` poses of the driver's turn (each gear's reference spoke — the driver's
    pitch point at driver angle 0, the driven's at the law's start — and the line of centres
    through the pitch point)."""
    check_int("n", n, 8, 100_000)
    a = driven_axis(pair)
    sense = -1.0 if pair.mesh == "external" else 1.0  # the driven's body angle is sense * ψ
    turn0 = float(driven_turn(pair, np.zeros(1))[0])
    c0, s0 = math.cos(turn0), math.sin(turn0)
    gap = np.full((1, 2), np.nan)
    drivers, drivens = [], []
    for m, phi in _motion_angles(pair, 721):
        r1 = pair.r1(phi, motion=m)
        drivers += [np.stack([r1 * np.cos(phi), r1 * np.sin(phi)], axis=1), gap]
        body = sense * pair.psi_in(m, phi)
        r2 = pair.r2(phi, motion=m)
        x, y = r2 * np.cos(body), r2 * np.sin(body)
        drivens += [np.stack([a + c0 * x - s0 * y, s0 * x + c0 * y], axis=1), gap]
    dwells = []
    for d in pair.law.dwells:
        phi = np.linspace(math.radians(d.start), math.radians(d.end), 181)
        r = pair.driver.r(phi)
        dwells += [np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1), gap]
    curves = Panel(
        f"pitch curves, a = {pair.centre_distance:.3f} mm",
        (
            Curve("driver sectors", np.vstack(drivers[:-1])),
            Curve("driver over the dwells (sector radius; the lock is cut smaller)", np.vstack(dwells[:-1])),
            Curve("driven", np.vstack(drivens[:-1])),
            Curve("centres", np.array([[0.0, 0.0], [a, 0.0]]), kind="mark"),
        ),
    )
    grid = np.radians(np.linspace(0.0, 360.0, 1441))
    ratio = Panel(
        "ratio w2/w1 over the driver angle",
        (Curve("w2/w1", np.stack([np.degrees(grid), pair.law.ratio(grid)], axis=1)),),
        "driver angle (deg)",
        "w2/w1",
        equal=False,
    )
    nus = []
    for m, phi in _motion_angles(pair, 721):
        deg = np.mod(np.degrees(phi), 360.0)
        nu = np.degrees(pair.pressure_deviation(phi, m))
        cut = np.flatnonzero(np.diff(deg) < 0) + 1  # a motion across 360 deg drawn in two pieces
        for piece_deg, piece_nu in zip(np.split(deg, cut), np.split(nu, cut), strict=True):
            nus += [np.stack([piece_deg, piece_nu], axis=1), gap]
    pressure = [Curve("pressure deviation", np.vstack(nus[:-1]))]
    if max_pressure_deviation_deg is not None:
        lim = max_pressure_deviation_deg
        pressure.append(
            Curve("limit", np.array([[0.0, lim], [360.0, lim], [np.nan, np.nan], [0.0, -lim], [360.0, -lim]]))
        )
    deviation = Panel(
        "pitch-curve pressure deviation", tuple(pressure), "driver angle (deg)", "deviation (deg)", equal=False
    )
    # the poses: each gear's spoke and the line of centres through the pitch point
    deg = 360.0 * np.arange(n) / n
    phi = np.radians(deg)
    start = math.radians(pair.law.segments[0].start)
    spoke1 = float(pair.driver.r(np.array([0.0]))[0])
    spoke2 = float(abs(pair.driver.r(np.array([start]))[0] - a))
    t2 = driven_turn(pair, phi)
    pitch = pair.driver.r(phi)
    zeros, ones = np.zeros(n), np.ones(n)
    lines = np.stack(
        [
            np.stack([zeros, zeros], axis=1),
            np.stack([spoke1 * np.cos(-phi), spoke1 * np.sin(-phi)], axis=1),
            np.full((n, 2), np.nan),
            np.stack([a * ones, zeros], axis=1),
            np.stack([a + spoke2 * np.cos(t2), spoke2 * np.sin(t2)], axis=1),
            np.full((n, 2), np.nan),
            np.stack([zeros, zeros], axis=1),
            np.stack([pitch, zeros], axis=1),
            np.stack([a * ones, zeros], axis=1),
        ],
        axis=1,
    )
    pose = Pose(deg, lines, 0, "driver angle (deg)")
    return DesignView((curves, ratio, deviation), rows, pose, notes)
