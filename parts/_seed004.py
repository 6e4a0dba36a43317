"""Seed 004 (Zhou et al. 2022) as published, our reading of it, and the design problem around it.

This is the design model behind ``planetary_seed004.py`` (the part script imports it; the
leading ``_`` keeps the builder from taking it for a part script).
``transplanter optimise parts/_seed004.py --seed 1`` runs :func:`problem`.

Published parameters: n = 4, r0..r10 at θ = 0, 30, ..., 300 deg (r11 at 330 deg is missing
from the paper), φH0 = 40 deg, S = 150 mm, β = -40 deg, H1 = 80 mm, seedling box at
(Yx, Yy) = (165, 70) mm inclined at Ya = 52 deg; three planets at 120 deg.

Reading (the paper does not say which gear the radii describe nor what θ measures):

* n = 4 is the ring:planet lobe ratio — a 4-lobed ring and a 1-lobed planet. With three
  planets at 120 deg the arms are identical only if ``(n - 1)/3`` is an integer, so n = 4
  is the smallest workable choice, and the ring must turn at ω1/ω2 = 3/4 of the carrier
  speed for the arm to return to its attitude every carrier turn without net rotation.
* r_i is the ring's pitch radius at the meshing point when the carrier has turned θ_i
  from the start (θ is the carrier angle, the paper's "known variable"). Over one carrier
  turn the carrier advances a quarter turn in the ring, so the ring's pitch curve is the
  r_i spline compressed to a 90 deg lobe: ring body angle = -θ/4 (the ring turns
  counter-clockwise relative to the carrier, eq. 4). The planet is its conjugate; the
  centre distance |OO1| = 57.749 mm (not published) is what closes the planet.
* r11 is missing: the periodic cubic spline runs through the 11 published radii only.
  ``VARIANTS`` shows what the results depend on (r11 = 94..100 mm, quintic spline).

The other readings fail: radii describing the planet (ring = 4-lobed conjugate) need
|OO1| = 260.6 mm and give a 550 mm trajectory; radii over the ring's full turn (one lobe)
cannot mesh with any closed planet.

Under this reading the trajectory comes out close to the paper (picking 337.3 vs 342 deg,
pushing 289.4 vs 296 deg, difference 47.9 vs 46 deg) but the gear pair is extreme: the planet
pitch curve passes 3.84 mm from its axis and the pitch-curve pressure deviation reaches
64.5 deg.

**The design problem.** :func:`problem` keeps the paper's layout (4:1 lobes, three planets)
and searches the ratio law, carrier radius and arm against the paper's twelve objectives
(``transplanter.design.objectives``) for the largest module that meshes and can be cut. The speed
ratio is not a free choice: ω1/ω2 = 1 - 1/n1 is the only one that returns the arm to its
attitude each carrier turn, so the lobe number carries it. ``OPTIMUM`` is what it found.

**Under issue 27's stricter rules** the teeth must keep ring tips of at least 0.6 m
(``RING_ADDENDUM_MIN``; the earlier design trimmed them to 0.43 m) and a mean contact ratio of
1.4 (``CONTACT_RATIO_MIN``), and the objectives are judged with the planets anywhere in their
play (:func:`objectives_under_play`), where v, i and vi must keep 2 deg, 3 mm and 2 mm
(``MARGINS_UNDER_PLAY``). ``problem(min_module=m)`` asks the other question of the same
design space — the largest smallest margin at a module of at least m — and its answers
(``FRONT_*``) are the Pareto front the train's study plots (:func:`front_points`).
"""

import dataclasses
import functools
import math

import numpy as np

from transplanter.core.errors import GeometryError
from transplanter.design.objectives import MIN_MODULE_MM, Site, seed004_objectives, worst_of
from transplanter.design.optimise import Problem
from transplanter.design.planetary import ArmGeometry, DifferentialTrain
from transplanter.design.train_view import differential_train_view
from transplanter.design.views import DesignView, Kept, Row, rows_from_objectives
from transplanter.geometry.backlash import design_backlash
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.cutter_choice import coarsest_cut
from transplanter.geometry.interference import pair_limits, screen_module
from transplanter.geometry.pitch import GearPair, PitchCurve
from transplanter.proof.train_rebuild import meshed_train
from transplanter.shop.solids import key_for

# -- as published ------------------------------------------------------------------------

LOBES = 4  # n
CARRIER_ANGLES_DEG = (0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300)
RING_RADII_MM = (100.0, 98.5, 101.0, 81.0, 82.0, 66.0, 64.0, 79.5, 83.0, 95.0, 98.0)
CARRIER_START = math.radians(40.0)  # φH0
ARM = ArmGeometry(tip=150.0, knee=80.0, mount=math.radians(-40.0))  # S, H1, β
SEEDLING_BOX = (165.0, 70.0)  # (Yx, Yy), mm
PLANT_SPACING = 120.0  # mm, mid of the paper's 60-180 mm range
PLANTING_DEPTH = 30.0  # mm, not published
SITE = Site(SEEDLING_BOX, math.radians(52.0), PLANT_SPACING, PLANTING_DEPTH)  # Ya = 52 deg
PUBLISHED = (
    ("trajectory height", 245.0, "mm"),
    ("picking angle", 342.0, "deg"),
    ("pushing angle", 296.0, "deg"),
    ("angle difference", 46.0, "deg"),
)
PUBLISHED_MODULE = 2.78  # mm

# -- our reading -------------------------------------------------------------------------


def ring_curve(r11: float | None = None, degree: int = 3) -> PitchCurve:
    """The ring's 4-lobed pitch curve from the published radii (see the reading above)."""
    theta = list(CARRIER_ANGLES_DEG) + ([330] if r11 is not None else [])
    radii = list(RING_RADII_MM) + ([r11] if r11 is not None else [])
    body = np.mod(-np.radians(theta) / LOBES, 2 * math.pi / LOBES)
    order = np.argsort(body)
    return PitchCurve.from_polar_points(body[order], np.asarray(radii)[order], lobes=LOBES, degree=degree)


def gear_pair(r11: float | None = None, degree: int = 3) -> GearPair:
    """The published ring with its conjugate one-lobed planet."""
    return GearPair.from_driver(ring_curve(r11, degree), "internal", driven_lobes=1)


def train(r11: float | None = None, degree: int = 3) -> DifferentialTrain:
    """The published train: the pair, the paper's arm and start, three planets."""
    return DifferentialTrain(gear_pair(r11, degree), ARM, CARRIER_START, planets=3)


VARIANTS = tuple((f"r11 = {r:g} mm", (r, 3)) for r in (94.0, 96.0, 98.0, 100.0)) + (("quintic spline", (None, 5)),)

# -- the design problem ------------------------------------------------------------------

LOBE_CHOICES = (4, 7)  # ring lobes with a one-lobed planet: (n1 - 1)/3 whole for three planets
PLANET_BORE = 10.0  # mm, planet shaft with a DIN 6885 key (3 x 3)
MIN_WALL = 3.0  # mm between the planet's keyway and its deepest tooth space
MAX_PRESSURE_DEVIATION_DEG = 30.0  # ν: the working pressure angle reaches α + ν = 50 deg
GOAL_MODULE = 3.5  # mm: the search stops rewarding a coarser module beyond this
VARIABLES = (
    ("lobe_choice", 0.0, 1.999),
    ("carrier_radius_mm", 45.0, 110.0),
    ("amplitude1", 0.15, 0.6),
    ("phase1_deg", 0.0, 360.0),
    ("amplitude2", 0.0, 0.2),
    ("phase2_deg", 0.0, 360.0),
    ("amplitude3", 0.0, 0.08),
    ("phase3_deg", 0.0, 360.0),
    ("carrier_start_deg", 0.0, 120.0),
    ("tip_S_mm", 130.0, 260.0),
    ("knee_H1_mm", 50.0, 140.0),
    ("mount_beta_deg", -100.0, 20.0),
)


def design_train(x) -> DifferentialTrain:
    """The train of a design vector (``VARIABLES`` order)."""
    lobes = LOBE_CHOICES[int(x[0])]
    harmonics = tuple(
        (x[k] * math.cos(math.radians(x[k + 1])), x[k] * math.sin(math.radians(x[k + 1]))) for k in (2, 4, 6)
    )
    return DifferentialTrain.from_ratio(lobes, harmonics, float(x[1]), design_arm(x), math.radians(x[8]), planets=3)


def design_arm(x) -> ArmGeometry:
    """The arm of a design vector: S, H1, β (the last three variables)."""
    return ArmGeometry(tip=float(x[9]), knee=float(x[10]), mount=math.radians(x[11]))


# Issue 27's stricter design (hard: below; the objectives' margins under the pair's own play)
RING_ADDENDUM_MIN = 0.6  # modules: the ring's tips at least this long (were trimmed to 0.43)
CONTACT_RATIO_MIN = 1.4  # mean over the cycle, closed form (the meshing proof measures it on the parts)
#: margins the objectives must keep with the planets anywhere in their play (issue 27)
MARGINS_UNDER_PLAY = {"i": 3.0, "v": 2.0, "vi": 2.0}
#: the play the search allows for, as a multiple of the ISO/TR 10064-2 backlash: the pair is cut
#: with the ISO figure plus what its dips take (its smallest free play must still reach the ISO
#: figure), and the free play grows with the pitch curve's pressure deviation — the shipped
#: pair's largest free play over its ISO target (measured by the build, its manifest) stays under it
PLAY_ALLOWANCE = 1.6


def play_turn(train: DifferentialTrain, module: float) -> float:
    """The planet's turn (rad) either way that the search allows for its play: half of
    ``PLAY_ALLOWANCE`` ISO backlashes over the planet's least pitch radius."""
    pair = train.pair
    iso = design_backlash(module, pair.centre_distance)
    return PLAY_ALLOWANCE * iso / 2 / pair.driven.min_radius().value


def objectives_under_play(train: DifferentialTrain, module: float, n: int = 720) -> tuple:
    """Each objective at its worst over the planets at the design place and at either end of
    :func:`play_turn` (constant turn): the values a design search can hold to margins."""
    turn = play_turn(train, module)
    played = [meshed_train(train, (0.0, math.pi), (sign * turn, sign * turn)) for sign in (-1.0, 1.0)]
    return worst_of(*(seed004_objectives(t, SITE, module, n=n) for t in (train, *played)))


def mean_contact_ratio(pair, found) -> float:
    """The closed-form contact ratio of ``found``'s teeth averaged over the cycle (the equivalent
    circular pair at every position, :func:`interference.pair_limits`): what the meshing proof's
    mean count of contacts measures on the cut parts (it finds a little more: tips that touch)."""
    sized, _ = pair.sized(teeth=found.teeth[0])
    lim = pair_limits(
        sized,
        ShaperCutter(found.cutter_teeth, found.module),
        ring_addendum=found.ring_addendum,
        pinion_addendum=found.pinion_addendum,
    )
    return float(np.nanmean(lim.contact_ratio))


def coarsest_module(pair, cut: bool = False):
    """The coarsest tooth count (module 2..6 mm) whose teeth pass the fouling screen with the
    ring's tips at least ``RING_ADDENDUM_MIN`` long and a mean contact ratio of at least
    ``CONTACT_RATIO_MIN``; with ``cut`` confirmed by cutting them (``coarsest_cut``). None: none."""
    limit = 6.0
    search = coarsest_cut if cut else screen_module
    while True:
        found = search(pair, max_module=limit, min_module=2.0, min_ring_addendum=RING_ADDENDUM_MIN)
        if found is None or mean_contact_ratio(pair, found) >= CONTACT_RATIO_MIN:
            return found
        limit = found.module * (1 - 1e-9)


def cuttability(train: DifferentialTrain, module: float, found=None) -> tuple[tuple[str, float, float, str], ...]:
    """(what, value, limit, unit) of the gear rules beside the paper's objectives: pressure
    deviation ν of both curves, room for the planet's shaft and key under its tooth spaces, and
    with ``found`` (the screened teeth) the ring's addendum and the mean contact ratio."""
    pair = train.pair
    nu = math.degrees(max(pair.driver.max_pressure_deviation(), pair.driven.max_pressure_deviation()))
    room = pair.driven.min_radius().value - 1.25 * module - PLANET_BORE / 2 - key_for(PLANET_BORE).hub_depth
    rules = (
        ("pitch-curve pressure deviation ν", nu, MAX_PRESSURE_DEVIATION_DEG, "deg"),
        ("planet wall under the keyway", room, MIN_WALL, "mm"),
    )
    if found is None:
        return rules
    return rules + (
        ("ring addendum", found.ring_addendum, RING_ADDENDUM_MIN, "m"),
        ("mean contact ratio", mean_contact_ratio(pair, found), CONTACT_RATIO_MIN, ""),
    )


def evaluate(x, cut: bool = True):
    """(train, teeth found, objectives under play, gear rules) of a design vector. The module is
    the coarsest :func:`coarsest_module` passes; with ``cut`` it is then confirmed by cutting the
    teeth — the search does so only for designs that nearly meet the rest."""
    train = design_train(x)
    found = coarsest_module(train.pair, cut=cut)
    module = found.module if found is not None else 0.0
    objectives = objectives_under_play(train, max(module, 1.0))
    if found is None:  # no module >= 2 mm meshes: objective xi reads 0
        objectives = tuple(dataclasses.replace(o, value=0.0) if o.number == "xi" else o for o in objectives)
    return train, found, objectives, cuttability(train, module, found)


#: half of a search's first population is drawn within this fraction of each range around OPTIMUM
SPREAD = 0.05
#: pass/fail objectives (margin 0 when met): not part of the smallest margin, a miss is a shortfall
BINARY = ("vii", "viii")


def margin_shortfall(o) -> float:
    """How far objective ``o`` falls short of the margin it must keep under play (0: kept)."""
    return max(0.0, MARGINS_UNDER_PLAY.get(o.number, 0.0) - o.margin)


def smallest_margin(objectives) -> tuple[str, float]:
    """The objective with the least margin beyond what it must keep under play, and that margin
    (mm or deg; a missed pass/fail objective counts its shortfall): the trade-off's second axis.
    The module (xi) is the first axis, not counted here."""
    rows = [
        (f"{o.number} {o.name}", o.margin - MARGINS_UNDER_PLAY.get(o.number, 0.0))
        for o in objectives
        if o.number != "xi" and (o.number not in BINARY or not o.ok)
    ]
    return min(rows, key=lambda r: r[1])


def _rules_short(rules) -> float:
    """How far the first two gear rules of :func:`cuttability` are missed: ν over its limit (deg)
    plus the planet's wall under its (mm); 0 when both hold."""
    return max(0.0, rules[0][1] - rules[0][2]) + max(0.0, rules[1][2] - rules[1][1])


def _shortfall(objectives, rules) -> float:
    """Objectives missed or short of their margins under play, in units of 5 deg / 5 mm (0.5 mm
    of module), and the gear rules."""
    out = sum(margin_shortfall(o) / (0.5 if o.number == "xi" else 5.0) for o in objectives)
    return out + _rules_short(rules) / 5.0


def problem(min_module: float | None = None) -> Problem:
    """Largest module whose teeth keep ``RING_ADDENDUM_MIN`` and ``CONTACT_RATIO_MIN``, with
    every objective of seed 004 met and the margins ``MARGINS_UNDER_PLAY`` kept with the planets
    anywhere in their play (penalties in units of 5 deg or 5 mm of shortfall), and the gear rules
    of :func:`cuttability`.

    With ``min_module`` (mm): a point of the Pareto front instead — the design with the largest
    :func:`smallest_margin` under play among those that meet every objective at the design
    place and whose teeth (same rules) are at least that coarse
    (``transplanter optimise parts/_seed004.py --set min_module=2.8 --write`` records it as
    ``FRONT_280``); every level's search starts around ``OPTIMUM``."""

    def cost(x):
        train, found, objectives, rules = evaluate(x, cut=False)
        shortfall = _shortfall(objectives, rules)
        if found is not None and shortfall < 1.0:  # nearly there: confirm the module by cutting
            train, found, objectives, rules = evaluate(x, cut=True)
            shortfall = _shortfall(objectives, rules)
        module = found.module if found is not None else 0.0
        return 10.0 * shortfall + (GOAL_MODULE - min(module, GOAL_MODULE))

    def front_cost(x):
        train, found, objectives, rules = evaluate(x, cut=False)
        module = found.module if found is not None else 0.0
        missed = sum(o.shortfall for o in seed004_objectives(train, SITE, max(module, 1.0), n=720) if o.number != "xi")
        hard = max(0.0, min_module - module) / 0.5 + (_rules_short(rules) + missed) / 5.0
        return 10.0 * hard - smallest_margin(objectives)[1]

    if min_module is None:
        return Problem(
            "seed004 differential train",
            VARIABLES,
            cost,
            infeasible=1e4,
            choices=("lobe_choice",),
            describe=describe,
            view=view,
            optimum="OPTIMUM",  # `transplanter optimise parts/_seed004.py --write` records it below
            x0=OPTIMUM,
            spread=SPREAD,
        )
    return Problem(
        f"seed004 front, module >= {min_module:g} mm",
        VARIABLES,
        front_cost,
        infeasible=1e4,
        choices=("lobe_choice",),
        describe=describe,
        view=functools.partial(view, written=f"FRONT_{round(min_module * 100)}"),
        optimum=f"FRONT_{round(min_module * 100)}",
        x0=OPTIMUM,
        spread=SPREAD,
    )


_SCREENED = Kept(8)


def _screened(gears: tuple):
    """The train of the gear variables ``gears`` (the first eight) and its coarsest module that
    passes the fouling screen (``coarsest_module``), kept for the studio: moving the carrier's
    start or the arm does not change the pair."""

    def make():
        train = design_train(gears + tuple(OPTIMUM[len(gears) :]))
        return train, coarsest_module(train.pair)

    return _SCREENED.get(gears, make)


def _rule_rows(rules) -> tuple[Row, ...]:
    """Rows of :func:`cuttability`'s gear rules (the first an upper limit, the rest lower ones)."""
    return tuple(
        Row(
            what,
            value,
            unit,
            f"{'<=' if k == 0 else '>='} {limit:g} {unit}".strip(),
            (limit - value) if k == 0 else (value - limit),
            (value <= limit) if k == 0 else (value >= limit),
        )
        for k, (what, value, limit, unit) in enumerate(rules)
    )


def view(x, written: str = "OPTIMUM"):
    """What ``transplanter design`` draws of design ``x``: the train's tip, attitude, pitch curves
    and the twelve objectives at the design place, the module the search measures (the fouling
    screen under the rules above, teeth not cut); then (``later``) :func:`as_built` — what the
    build would make of it written as ``written`` and whether it would refuse it."""
    x = tuple(float(v) for v in x)
    pair_train, found = _screened(x[:8])
    train = dataclasses.replace(pair_train, arm=design_arm(x), carrier_start=math.radians(x[8]))
    module = found.module if found is not None else 0.0
    shown = differential_train_view(train, SITE, max(module, 1.0))
    if found is None:  # no module >= 2 mm meshes: objective xi reads 0, as the search scores it
        shown = dataclasses.replace(
            shown,
            rows=tuple(
                dataclasses.replace(r, value=0.0, margin=-MIN_MODULE_MM, ok=False) if r.name.startswith("xi ") else r
                for r in shown.rows
            ),
        )

    notes = (
        f"module {module:.3f} mm: the coarsest the fouling screen passes with ring tips >= {RING_ADDENDUM_MIN:g} m "
        f"and a mean contact ratio >= {CONTACT_RATIO_MIN:g} (teeth not cut, 720 samples: the search's measure)",
        *shown.notes,
    )
    return dataclasses.replace(
        shown,
        notes=notes,
        later=functools.partial(as_built, x, written),
        later_title=f"as the build makes it, written as {written}",
    )


def describe(x) -> dict[str, str]:
    """Each objective of a design (module from the screen, teeth not cut) at its worst under the
    play, with its margin: how far inside its limits it is (negative: how far outside)."""
    _, found, objectives, rules = evaluate(x, cut=False)
    out = {}
    for o in objectives:
        out[f"{o.number} {o.name}"] = f"{o.value:.4g} {o.unit} (margin {o.margin:+.3g})".replace("  ", " ")
    for what, value, limit, unit in rules:
        out[what] = f"{value:.4g} {unit} (limit {limit:g})".replace("  ", " ")
    return out


#: the design problem() found *before* issue 27's rules (the objectives at the design place only,
#: ring tips trimmed as short as the screen liked — 0.43 m when cut): ``transplanter optimise
#: parts/_seed004.py --seed 1 --maxiter 150 --popsize 8 --workers 2`` reached cost 0.197 (every
#: objective met except ν = 30.1 deg, module 3.55 mm) in 32 min on 2 cores; differential evolution
#: within ±3 % of each variable's range around it (seed 2, 25 generations) then met ν too (cost 0,
#: module 3.52 mm). Kept as the earlier design the train's study compares, and where the front's
#: searches start. ``VARIABLES`` order; lobe_choice < 1: 4 ring lobes.
OPTIMUM = (
    0.556964,
    79.679167,
    0.40482,
    170.14568,
    0.077232,
    339.996376,
    0.017306,
    153.125484,
    17.773839,
    167.859952,
    69.000788,
    -37.930985,
)


def scaled(x, factor: float) -> tuple:
    """The design ``x`` with its ratio variation (harmonic amplitudes) scaled by ``factor``."""
    return tuple(v * factor if k in (2, 4, 6) else v for k, v in enumerate(x))


# -- the Pareto front ----------------------------------------------------------------------
#: the least modules (mm) of the front's points: ``transplanter optimise parts/_seed004.py --set
#: min_module=2.5 --seed 1 --maxiter 80 --popsize 10 --workers 2 --write`` recorded ``FRONT_250``
#: (9 720 designs, 28 min on 2 cores; best cost 1.82: 96/24 teeth at 2.51 mm, every objective met
#: but viii by 0.14 mm, ν 30.18 deg); ``FRONT_280`` and ``FRONT_310`` the same with ``--maxiter 25``
#: (~8 min each: 80/20 teeth at 2.92 mm with every objective met but ν 32.18 deg; 76/19 at 3.11 mm,
#: ν 31.79 deg and viii missed by 0.24 mm). None is feasible: see ``made_design``. At m >= 2.2 mm
#: (25 generations) the search found nothing better than OPTIMUM itself (2.22 mm, 1.95 short).
FRONT_LEVELS = (2.5, 2.8, 3.1)
FRONT_250 = (
    0.8233979976546597,
    80.27455568918295,
    0.40475647101534795,
    169.68626197644426,
    0.0826024316985922,
    339.47024021886966,
    0.01646510426208542,
    146.07797197667014,
    17.914039244424266,
    169.59427363814584,
    71.00908979897436,
    -38.25319675214526,
)
FRONT_280 = (
    0.27989345768550533,
    77.5252926102855,
    0.4156006022474395,
    170.33511953703237,
    0.09067484916797386,
    340.20334360430616,
    0.01301143553400294,
    158.9435526440297,
    20.93762206363533,
    166.18038053032828,
    72.70424504671917,
    -37.76243033895689,
)
FRONT_310 = (
    0.6377182875302985,
    79.03700385447357,
    0.4028093169854707,
    167.38049021866996,
    0.0908981020590332,
    333.286262496855,
    0.011772738560614063,
    160.3918802566342,
    17.711818197806537,
    166.26396888109036,
    72.83630908300454,
    -35.5931826043911,
)


_FRONT = Kept(16)


def _front_point(x: tuple, level: float = 0.0):
    """A design as the front's search measures it: (module under the rules above, smallest margin
    under play, the objective that has it, feasible: every objective but the module (the front's
    other axis) met at the design place, the gear rules kept and the module at least ``level``);
    kept (``views.Kept``: the studio's view reaches it, and a search's workers receive the view)."""
    return _FRONT.get((tuple(x), level), lambda: _measured_front_point(x, level))


def _measured_front_point(x: tuple, level: float):
    train, found, objectives, rules = evaluate(x, cut=False)
    module = found.module if found is not None else 0.0
    nominal = seed004_objectives(train, SITE, max(module, 1.0), n=720)
    binding, margin = smallest_margin(objectives)
    feasible = module >= level and _rules_short(rules) == 0 and all(o.ok for o in nominal if o.number != "xi")
    return module, margin, binding, feasible


def made_design(**written):
    """(design vector, its teeth: ``ScreenResult``) the part script makes: the front's feasible
    point with the coarsest module that meets objective xi too, cut under the rules above; where
    the front has none, OPTIMUM cut as before issue 27 (the ring's tips trimmed as short as the
    screen needs) — the nearest design that can be built, which the train's study says.

    ``written``: a design in place of one of those tuples (``OPTIMUM=x``, ``FRONT_280=x``) — what
    the build would make were it written there (the studio asks before it writes)."""
    found = []
    for level in FRONT_LEVELS:
        name = f"FRONT_{round(level * 100)}"
        x = written.get(name, globals()[name])
        module, margin, _, feasible = _front_point(tuple(x), level)
        if feasible and module >= MIN_MODULE_MM:
            found.append((module, margin, x))
    if found:
        x = max(found, key=lambda f: (f[0], f[1]))[2]
        return x, coarsest_module(design_train(x).pair, cut=True)
    x = written.get("OPTIMUM", OPTIMUM)
    return x, coarsest_cut(design_train(x).pair, max_module=6.0, min_module=2.0)


def as_built(x, written: str = "OPTIMUM") -> DesignView:
    """What ``transplanter build`` would make of design ``x`` written as ``written`` (a tuple
    :func:`made_design` reads) and whether it would refuse it, judged as the build judges: the
    teeth cut as :func:`made_design` cuts them (``coarsest_cut``: seconds), the twelve objectives
    at the design place at that module over ``seed004_objectives``' 1440 samples — the
    ``optimised_train`` study's own call, which refuses a miss (``must_meet``) —, each at its
    worst under the planets' play at that module (the margins ``MARGINS_UNDER_PLAY`` the train's
    proof states), and the gear rules of :func:`cuttability`. The build proves the made parts
    besides (meshing, backlash, the machine's clearances), which this does not."""
    x = tuple(float(v) for v in x)
    made, cut = made_design(**{written: x})
    if tuple(float(v) for v in made) != x:
        other = next(
            (n for n in ("OPTIMUM", *(f"FRONT_{round(lv * 100)}" for lv in FRONT_LEVELS)) if globals()[n] == made),
            "another design",
        )
        raise GeometryError(
            f"the build would make {other}, not this design: written as {written} it is not the front's coarsest "
            "feasible point (made_design)"
        )
    train = design_train(x)
    if cut is None:
        raise GeometryError("the build would refuse it: no module of 2-6 mm passes the fouling screen and cuts")
    at_place = seed004_objectives(train, SITE, cut.module)  # the optimised_train study's call
    missed = [
        f"{o.number} {o.name} {o.value:.4g} {o.unit} ({o.limit})".replace("  ", " ") for o in at_place if not o.ok
    ]
    verdict = (
        "the build would refuse optimised_train (a missed objective): " + "; ".join(missed)
        if missed
        else "the build would make it: every objective met at the design place"
    )
    teeth = f"{cut.teeth[0]}/{cut.teeth[1]} teeth at m = {cut.module:.3f} mm, ring tips {cut.ring_addendum:.2f} m"
    under = objectives_under_play(train, cut.module)
    marked = tuple(
        dataclasses.replace(r, name=f"{r.name} (under play)")
        for r in rows_from_objectives(under)
        if r.name[:3] != "xi "
    )
    how = f"cut as the build cuts it ({written}): {teeth}"
    if written == "OPTIMUM":  # made_design's fallback: the rules before issue 27 (see the rows)
        how += "; OPTIMUM is cut under the rules before issue 27, its ring tips as short as the screen needs"
    short = [r.name for r in marked if not r.ok]
    besides = (
        "under the planets' play the build states each objective's worst (the train's proof) and refuses none"
        + (f": here {len(short)} short ({'; '.join(short)})" if short else "")
        + "; it also proves the made parts (meshing, backlash, the machine's clearances), which this does not"
    )
    return DesignView(
        rows=rows_from_objectives(at_place) + marked + _rule_rows(cuttability(train, cut.module, cut)),
        notes=(verdict, how, besides),
    )


def front_design(level: float) -> tuple:
    """(design vector, module under the rules above) of the front's point at ``level`` mm."""
    x = globals()[f"FRONT_{round(level * 100)}"]
    return x, _front_point(tuple(x), level)[0]


def front_points(made, made_module: float) -> tuple:
    """The Pareto front's designs (``FRONT_*``) and OPTIMUM, each measured as the search measures
    them, and the design ``made`` as it is made (cut at ``made_module`` mm): ``families.FrontPoint``
    each — the made one chosen, counted on the front only if it keeps the rules above."""
    from transplanter.families import FrontPoint

    out = []
    if made is OPTIMUM:  # made under the earlier rules: its own point, at the module it is cut at
        binding, margin = smallest_margin(objectives_under_play(design_train(OPTIMUM), made_module))
        out.append(FrontPoint("made: OPTIMUM, ring tips 0.43 m", made_module, margin, binding, True, False))
    module, margin, binding, feasible = _front_point(tuple(OPTIMUM))
    out.append(FrontPoint("OPTIMUM with 0.6 m ring tips", module, margin, binding, False, feasible))
    for level in FRONT_LEVELS:
        x = globals()[f"FRONT_{round(level * 100)}"]
        module, margin, binding, feasible = _front_point(tuple(x), level)
        chosen = made is not OPTIMUM and tuple(x) == tuple(made)
        out.append(FrontPoint(f"best at m >= {level:g} mm", module, margin, binding, chosen, feasible))
    return tuple(out)
